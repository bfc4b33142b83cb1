#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "core/errors.hpp"
#include "io/recording.hpp"
#include "recording_fixtures.hpp"

using namespace dexcloth;
using namespace dexcloth::io;
using namespace dexcloth::io::testing;
namespace fs = std::filesystem;

namespace {

// Bit pattern of the float32 a double is stored as.
std::uint32_t float_bits(double x) {
  const float f = static_cast<float>(x);
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

// A read-back value must be exactly the float32 the writer stored, widened.
void expect_stored(double written, double read) {
  EXPECT_EQ(float_bits(written), float_bits(read));
  EXPECT_EQ(read, static_cast<double>(static_cast<float>(written)));
}

void expect_stored(const Vec3& written, const Vec3& read) {
  for (int i = 0; i < 3; ++i) expect_stored(written[i], read[i]);
}

void expect_stored(const Eigen::Quaterniond& written, const Eigen::Quaterniond& read) {
  expect_stored(written.coeffs().head<3>().eval(), read.coeffs().head<3>().eval());
  expect_stored(written.w(), read.w());
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_recording(const fs::path& dir, const RecordingHeader& h, int frames) {
  RecordingWriter w(dir, h);
  for (int k = 0; k < frames; ++k) w.write_frame(sample_frame(h, k));
  w.close();
}

template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

}  // namespace

TEST(Recording, RecordSizeMatchesDocumentedLayout) {
  const RecordingHeader h = sample_header();
  // 44 fixed + 12 per vertex (63 + 9) + 28 per shape (5) + 36 per contact + 40 per patch.
  EXPECT_EQ(frame_record_bytes(h, 0, 0), 44u + 12u * 72u + 28u * 5u);
  EXPECT_EQ(frame_record_bytes(h, 2, 1), 44u + 12u * 72u + 28u * 5u + 72u + 40u);
  // docs/recording-format.md: a 65×65 grid (4,225 vertices, 8,192 triangles) is 50,744 bytes.
  RecordingHeader big;
  big.cloths.push_back(grid_cloth("sheet", 65, 65, 1.0, 1.0, false));
  EXPECT_EQ(big.cloths[0].faces.rows(), 8192);
  EXPECT_EQ(frame_record_bytes(big, 0, 0), 50744u);
}

TEST(Recording, RoundTripIsBitExactInFloat32) {
  const fs::path dir = fresh_dir();
  const RecordingHeader h = sample_header();
  const int n = 6;
  write_recording(dir, h, n);

  const RecordingReader r(dir);
  ASSERT_EQ(r.frame_count(), n);
  EXPECT_TRUE(r.header().complete);
  EXPECT_EQ(r.header().scene, "unit test");
  EXPECT_EQ(r.header().dt, 0.005);
  EXPECT_EQ(r.header().frame_rate, 50.0);
  EXPECT_EQ(r.header().metadata.at("coupling"), "bai-liu");
  ASSERT_EQ(r.header().cloths.size(), 2u);
  EXPECT_EQ(r.header().cloths[0].faces, h.cloths[0].faces);
  EXPECT_EQ(r.header().cloths[0].face_uvs, h.cloths[0].face_uvs);
  EXPECT_EQ(r.header().cloths[1].face_uvs.rows(), 0);
  EXPECT_EQ(r.header().cloths[1].colour, h.cloths[1].colour);
  ASSERT_EQ(r.header().rigid_shapes.size(), 5u);
  for (std::size_t s = 0; s < 5; ++s) {
    EXPECT_EQ(r.header().rigid_shapes[s].type, h.rigid_shapes[s].type);
    EXPECT_EQ(r.header().rigid_shapes[s].name, h.rigid_shapes[s].name);
  }
  EXPECT_EQ(r.header().rigid_shapes[2].length, 0.025);
  EXPECT_EQ(r.header().rigid_shapes[4].mesh_faces, h.rigid_shapes[4].mesh_faces);
  EXPECT_EQ(r.header().rigid_shapes[4].mesh_vertices, h.rigid_shapes[4].mesh_vertices);

  // Frames read back in any order are the stored float32 values, bit for bit.
  for (const int k : {5, 0, 3, 1, 4, 2}) {
    const RecordingFrame in = sample_frame(h, k);
    const RecordingFrame out = r.read_frame(k);
    EXPECT_EQ(out.t, in.t);  // float64: exact
    EXPECT_EQ(out.step_ms, in.step_ms);
    ASSERT_EQ(out.cloth_positions.size(), 2u);
    for (std::size_t c = 0; c < 2; ++c) {
      ASSERT_EQ(out.cloth_positions[c].rows(), in.cloth_positions[c].rows());
      for (Eigen::Index i = 0; i < in.cloth_positions[c].size(); ++i)
        expect_stored(in.cloth_positions[c].data()[i], out.cloth_positions[c].data()[i]);
    }
    for (std::size_t s = 0; s < in.rigid_poses.size(); ++s) {
      expect_stored(in.rigid_poses[s].position, out.rigid_poses[s].position);
      expect_stored(in.rigid_poses[s].orientation, out.rigid_poses[s].orientation);
    }
    ASSERT_EQ(out.contacts.size(), static_cast<std::size_t>(k % 3));
    for (std::size_t i = 0; i < in.contacts.size(); ++i) {
      expect_stored(in.contacts[i].position, out.contacts[i].position);
      expect_stored(in.contacts[i].normal, out.contacts[i].normal);
      expect_stored(in.contacts[i].force, out.contacts[i].force);
    }
    ASSERT_EQ(out.patches.size(), static_cast<std::size_t>(k % 2));
    for (std::size_t i = 0; i < in.patches.size(); ++i) {
      expect_stored(in.patches[i].centre, out.patches[i].centre);
      expect_stored(in.patches[i].orientation, out.patches[i].orientation);
      expect_stored(in.patches[i].size, out.patches[i].size);
    }
  }

  // Writing what was read gives the same bytes.
  const fs::path dir2 = fresh_dir("_copy");
  {
    RecordingWriter w(dir2, r.header());
    for (long k = 0; k < n; ++k) w.write_frame(r.read_frame(k));
  }  // destructor finalises
  EXPECT_EQ(slurp(dir / k_frames_file), slurp(dir2 / k_frames_file));
  EXPECT_EQ(RecordingReader(dir2).frame_count(), n);
}

TEST(Recording, StreamsFramesBeforeClose) {
  const fs::path dir = fresh_dir();
  const RecordingHeader h = sample_header();
  RecordingWriter w(dir, h);
  w.write_frame(sample_frame(h, 0));
  w.write_frame(sample_frame(h, 1));

  // Unfinished: strict readers refuse, recover readers see the frames written so far.
  EXPECT_NE(error_of([&] { RecordingReader r(dir); }).find("not finalised"), std::string::npos);
  RecordingReader partial(dir, RecordingReader::Mode::recover);
  EXPECT_FALSE(partial.header().complete);
  EXPECT_EQ(partial.frame_count(), 2);
  expect_stored(sample_frame(h, 1).cloth_positions[0](3, 2),
                partial.read_frame(1).cloth_positions[0](3, 2));

  w.write_frame(sample_frame(h, 2));
  w.close();
  w.close();  // idempotent
  EXPECT_EQ(RecordingReader(dir).frame_count(), 3);
}

TEST(Recording, DetectsTruncation) {
  const fs::path dir = fresh_dir();
  const RecordingHeader h = sample_header();
  write_recording(dir, h, 4);
  const fs::path frames = dir / k_frames_file;
  const auto size = fs::file_size(frames);
  const auto last = frame_record_bytes(h, 3 % 3, 3 % 2);

  // Cut inside the last record, exactly at a record boundary, and inside the file header.
  for (const std::uintmax_t cut : {size - 10, size - last, std::uintmax_t{10}}) {
    write_recording(dir, h, 4);
    fs::resize_file(frames, cut);
    for (const auto mode : {RecordingReader::Mode::strict, RecordingReader::Mode::recover}) {
      const std::string e = error_of([&] { RecordingReader r(dir, mode); });
      EXPECT_NE(e.find(frames.string()), std::string::npos) << e;
      EXPECT_NE(e.find("truncated"), std::string::npos) << e;
    }
  }

  // Stray bytes after the last frame.
  write_recording(dir, h, 4);
  std::ofstream(frames, std::ios::binary | std::ios::app) << "junk";
  EXPECT_NE(error_of([&] { RecordingReader r(dir); }).find("4 stray bytes"), std::string::npos);
}

TEST(Recording, RecoversWholeFramesOfACrashedRun) {
  const fs::path dir = fresh_dir();
  const RecordingHeader h = sample_header();
  write_recording(dir, h, 3);
  // A crash leaves the unfinished header and a partly written record.
  RecordingHeader unfinished = h;
  std::ofstream(dir / k_header_file) << header_to_json(unfinished).dump();
  fs::resize_file(dir / k_frames_file, fs::file_size(dir / k_frames_file) - 7);

  EXPECT_THROW(RecordingReader r(dir), std::runtime_error);
  const RecordingReader r(dir, RecordingReader::Mode::recover);
  EXPECT_EQ(r.frame_count(), 2);
  expect_stored(sample_frame(h, 1).rigid_poses[2].position[0], r.read_frame(1).rigid_poses[2].position[0]);
}

TEST(Recording, DetectsCorruptRecords) {
  const fs::path dir = fresh_dir();
  const RecordingHeader h = sample_header();
  write_recording(dir, h, 3);
  const fs::path frames = dir / k_frames_file;
  const auto first = frame_record_bytes(h, 0, 0);

  // A flipped bit in frame 1's positions fails its CRC, and only frame 1.
  {
    std::fstream f(frames, std::ios::binary | std::ios::in | std::ios::out);
    f.seekp(static_cast<std::streamoff>(16 + first + 100));
    f.put('\x5a');
  }
  const RecordingReader r(dir);
  EXPECT_NO_THROW(r.read_frame(0));
  EXPECT_NO_THROW(r.read_frame(2));
  const std::string e = error_of([&] { r.read_frame(1); });
  EXPECT_NE(e.find("frame 1: corrupt (CRC mismatch)"), std::string::npos) << e;
  EXPECT_THROW(r.read_frame(3), std::out_of_range);

  // A bad record magic is reported at open.
  {
    std::fstream f(frames, std::ios::binary | std::ios::in | std::ios::out);
    f.seekp(16);
    f.put('Q');
  }
  EXPECT_NE(error_of([&] { RecordingReader r2(dir); }).find("bad record magic"), std::string::npos);
}

TEST(Recording, ReportsEveryHeaderProblemWithItsPointer) {
  const fs::path dir = fresh_dir();
  write_recording(dir, sample_header(), 1);
  nlohmann::json doc = nlohmann::json::parse(slurp(dir / k_header_file));
  doc["dt"] = -1;
  doc["cloths"][0]["faces"][2] = {0, 1, 999};
  doc["rigid_shapes"][2]["type"] = "cone";
  doc["rigid_shapes"][1].erase("radius");
  std::ofstream(dir / k_header_file) << doc.dump();
  try {
    RecordingReader r(dir);
    FAIL() << "expected InputRejected";
  } catch (const InputRejected& e) {
    const std::string s = e.what();
    EXPECT_EQ(e.errors().size(), 4u) << s;
    EXPECT_NE(s.find("recording.json: /dt: must be > 0, got -1"), std::string::npos) << s;
    EXPECT_NE(s.find("/cloths/0/faces/2: indices must be integers in [0, 63)"), std::string::npos)
        << s;
    EXPECT_NE(s.find("/rigid_shapes/2/type: must be box, sphere, capsule, plane or mesh"),
              std::string::npos)
        << s;
    EXPECT_NE(s.find("/rigid_shapes/1/radius: missing"), std::string::npos) << s;
  }

  std::ofstream(dir / k_header_file) << "{ not json";
  EXPECT_NE(error_of([&] { RecordingReader r(dir); }).find("not valid JSON"), std::string::npos);
}

TEST(Recording, ErrorsNameThePath) {
  const fs::path base = fresh_dir();
  // A folder below a regular file cannot be created.
  std::ofstream(base / "plain_file") << "x";
  const fs::path bad = base / "plain_file" / "rec";
  const std::string e = error_of([&] { RecordingWriter w(bad, sample_header()); });
  EXPECT_NE(e.find(bad.string()), std::string::npos) << e;

  const fs::path missing = base / "no_such_recording";
  const std::string e2 = error_of([&] { RecordingReader r(missing); });
  EXPECT_NE(e2.find((missing / k_header_file).string()), std::string::npos) << e2;
}

TEST(Recording, RejectsFramesThatDoNotMatchTheHeader) {
  const fs::path dir = fresh_dir();
  const RecordingHeader h = sample_header();
  RecordingWriter w(dir, h);
  RecordingFrame f = sample_frame(h, 0);
  f.cloth_positions[1].resize(4, 3);
  EXPECT_THROW(w.write_frame(f), std::invalid_argument);
  f = sample_frame(h, 0);
  f.rigid_poses.pop_back();
  EXPECT_THROW(w.write_frame(f), std::invalid_argument);
  w.write_frame(sample_frame(h, 0));
  w.close();
  EXPECT_EQ(RecordingReader(dir).frame_count(), 1);
  EXPECT_THROW(w.write_frame(sample_frame(h, 1)), std::logic_error);

  // An invalid header is rejected before anything is written.
  RecordingHeader bad = h;
  bad.cloths[0].faces(0, 0) = 1000;
  bad.frame_rate = 0.0;
  const fs::path dir2 = dir / "bad";
  EXPECT_THROW(RecordingWriter(dir2, bad), InputRejected);
  EXPECT_FALSE(fs::exists(dir2));
}

#include "io/viewer_launch.hpp"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string_view>

#include <sys/wait.h>
#include <unistd.h>

#include "io/recording.hpp"

#ifndef DEXCLOTH_VIEWER_DIR
#error "DEXCLOTH_VIEWER_DIR must be defined by src/io/CMakeLists.txt"
#endif

namespace dexcloth::io {
namespace {

namespace fs = std::filesystem;

constexpr const char* k_setup_hint = "run scripts/setup.sh (as root) to install it";

// First executable named `name` on $PATH (or `name` itself if it holds a slash).
std::optional<fs::path> find_program(const std::string& name) {
  if (name.find('/') != std::string::npos) {
    if (::access(name.c_str(), X_OK) == 0) return fs::path(name);
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  std::string_view rest = path ? path : "/usr/local/bin:/usr/bin:/bin";
  while (!rest.empty()) {
    const auto colon = rest.find(':');
    const std::string_view entry = rest.substr(0, colon);
    rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
    if (entry.empty()) continue;
    const fs::path candidate = fs::path(entry) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return std::nullopt;
}

fs::path require_node() {
  if (auto node = find_program("node")) return *node;
  throw std::runtime_error(std::string("node (Node.js) not found on PATH; ") + k_setup_hint);
}

// The viewer folder with its npm dependencies installed.
fs::path require_viewer() {
  const fs::path dir = viewer_dir();
  if (!fs::exists(dir / "serve.mjs"))
    throw std::runtime_error((dir / "serve.mjs").string() +
                             ": viewer not found (set DEXCLOTH_VIEWER_DIR to the viewer folder)");
  for (const char* package : {"three", "playwright-core"})
    if (!fs::exists(dir / "node_modules" / package / "package.json"))
      throw std::runtime_error((dir / "node_modules" / package).string() +
                               ": viewer dependencies missing; run scripts/setup.sh (it runs "
                               "`npm ci` in viewer/)");
  return dir;
}

// Chromium as snapshot.mjs will use it: $DEXCLOTH_CHROMIUM, else the first browser on PATH.
fs::path require_chromium() {
  if (const char* env = std::getenv("DEXCLOTH_CHROMIUM"); env && *env) {
    if (auto p = find_program(env)) return *p;
    throw std::runtime_error(std::string("DEXCLOTH_CHROMIUM=") + env + ": not an executable");
  }
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"})
    if (auto p = find_program(name)) return *p;
  throw std::runtime_error(std::string("chromium not found on PATH; ") + k_setup_hint);
}

// Checks the recording can be read (an unfinished one is fine: the viewer shows its frames).
RecordingReader require_recording(const std::string& dir) {
  return RecordingReader(dir, RecordingReader::Mode::recover);
}

// The running child, for the signal handler below.
volatile std::sig_atomic_t g_child_pid = 0;

// Passes SIGINT/SIGTERM on to the child, which decides how to stop; we wait for it.
extern "C" void forward_signal(int sig) {
  if (g_child_pid > 0) ::kill(static_cast<pid_t>(g_child_pid), sig);
}

// Runs `argv` as a child and waits for it; SIGINT and SIGTERM are forwarded to the child.
int run_child(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::cout.flush();
  std::cerr.flush();

  struct sigaction forward {}, old_int{}, old_term{};
  forward.sa_handler = forward_signal;
  sigemptyset(&forward.sa_mask);
  ::sigaction(SIGINT, &forward, &old_int);
  ::sigaction(SIGTERM, &forward, &old_term);

  const pid_t pid = ::fork();
  if (pid < 0) {
    ::sigaction(SIGINT, &old_int, nullptr);
    ::sigaction(SIGTERM, &old_term, nullptr);
    throw std::runtime_error("cannot start " + argv[0] + ": fork failed");
  }
  if (pid == 0) {
    // Child: default signal handling, then become node.
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    ::execv(args[0], args.data());
    std::perror(("exec " + argv[0]).c_str());
    ::_exit(127);
  }
  g_child_pid = pid;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  g_child_pid = 0;
  ::sigaction(SIGINT, &old_int, nullptr);
  ::sigaction(SIGTERM, &old_term, nullptr);
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return WTERMSIG(status) == SIGINT ? 0 : 128 + WTERMSIG(status);
  return 1;
}

}  // namespace

fs::path viewer_dir() {
  if (const char* env = std::getenv("DEXCLOTH_VIEWER_DIR"); env && *env) return fs::path(env);
  return fs::path(DEXCLOTH_VIEWER_DIR);
}

int run_viewer_server(const std::string& dir, int port) {
  if (port < 0 || port > 65535)
    throw std::runtime_error("--port: must be in [0, 65535], got " + std::to_string(port));
  const RecordingReader reader = require_recording(dir);
  const fs::path node = require_node();
  const fs::path viewer = require_viewer();
  std::cout << "dexcloth: viewing " << dir << " (" << reader.frame_count() << " frames"
            << (reader.header().complete ? "" : ", unfinished") << ")\n";
  return run_child({node.string(), (viewer / "serve.mjs").string(), dir, "--port",
                    std::to_string(port), "--host", "127.0.0.1"});
}

int run_snapshot(const std::string& dir, const std::vector<int>& frames, const std::string& png_dir,
                 const std::string& mp4) {
  const RecordingReader reader = require_recording(dir);
  for (const int k : frames)
    if (k < 0 || k >= reader.frame_count())
      throw std::runtime_error("--frames: frame " + std::to_string(k) + " not in " + dir +
                               " (it has " + std::to_string(reader.frame_count()) + " frames)");
  if (png_dir.empty() && mp4.empty())
    throw std::runtime_error("snapshot: nothing to do; give --png OUTDIR and/or --mp4 FILE");
  if (!png_dir.empty() && frames.empty())
    throw std::runtime_error("--frames: give the frames to write as PNGs, e.g. --frames 0,50,100");
  const fs::path node = require_node();
  const fs::path viewer = require_viewer();
  const fs::path chromium = require_chromium();
  if (!mp4.empty() && !find_program("ffmpeg"))
    throw std::runtime_error(std::string("ffmpeg not found on PATH (needed for --mp4); ") +
                             k_setup_hint);

  std::vector<std::string> argv{node.string(), (viewer / "snapshot.mjs").string(), dir,
                                "--chromium", chromium.string()};
  if (!frames.empty()) {
    std::string list;
    for (const int k : frames) {
      if (!list.empty()) list += ',';
      list += std::to_string(k);
    }
    argv.insert(argv.end(), {"--frames", list});
  }
  if (!png_dir.empty()) argv.insert(argv.end(), {"--png", png_dir});
  if (!mp4.empty()) argv.insert(argv.end(), {"--mp4", mp4});
  return run_child(argv);
}

}  // namespace dexcloth::io

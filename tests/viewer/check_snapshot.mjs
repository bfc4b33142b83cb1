// Runs viewer/snapshot.mjs as `dexcloth snapshot` does and checks its PNGs and MP4:
//   node check_snapshot.mjs RECORDING_DIR VIEWER_DIR OUTDIR
// Exit 0: pass; 1: fail; 77: skipped (Chromium, ffmpeg or the viewer's node_modules missing).
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const SKIP = 77;
const [recordingDir, viewerDir, outDir] = process.argv.slice(2);
if (!recordingDir || !viewerDir || !outDir) {
  console.error('usage: node check_snapshot.mjs RECORDING_DIR VIEWER_DIR OUTDIR');
  process.exit(2);
}

const failures = [];
const check = (ok, message) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${message}`);
  if (!ok) failures.push(message);
};

// Width and height from a PNG's IHDR chunk.
function pngSize(file) {
  const b = fs.readFileSync(file);
  if (b.length < 24 || b.readUInt32BE(0) !== 0x89504e47 || b.toString('ascii', 12, 16) !== 'IHDR') return null;
  return [b.readUInt32BE(16), b.readUInt32BE(20)];
}

async function main() {
  const { findChromium } = await import(pathToFileURL(path.join(viewerDir, 'snapshot.mjs')).href);
  if (!findChromium()) { console.log('SKIP: chromium not found on PATH; run scripts/setup.sh'); return SKIP; }
  for (const pkg of ['three', 'playwright-core']) {
    if (!fs.existsSync(path.join(viewerDir, 'node_modules', pkg, 'package.json'))) {
      console.log(`SKIP: ${path.join(viewerDir, 'node_modules', pkg)} missing; run scripts/setup.sh (npm ci in viewer/)`);
      return SKIP;
    }
  }
  if (spawnSync('ffmpeg', ['-version']).status !== 0 || spawnSync('ffprobe', ['-version']).status !== 0) {
    console.log('SKIP: ffmpeg/ffprobe not found on PATH; run scripts/setup.sh');
    return SKIP;
  }

  const header = JSON.parse(fs.readFileSync(path.join(recordingDir, 'recording.json'), 'utf8'));
  const last = header.frame_count - 1;
  fs.rmSync(outDir, { recursive: true, force: true });
  const png = path.join(outDir, 'png');
  const mp4 = path.join(outDir, 'clip.mp4');
  const snapshot = path.join(viewerDir, 'snapshot.mjs');

  // PNGs of two frames and a video of all frames, at an odd width (the encoder needs even).
  const run = spawnSync(process.execPath, [snapshot, recordingDir, '--frames', `0,${last}`, '--png', png,
    '--width', '641', '--height', '400'], { encoding: 'utf8' });
  process.stdout.write(run.stdout);
  process.stderr.write(run.stderr);
  check(run.status === 0, `snapshot --png exits 0 (got ${run.status})`);
  for (const k of [0, last]) {
    const file = path.join(png, `frame_${String(k).padStart(6, '0')}.png`);
    const size = fs.existsSync(file) ? pngSize(file) : null;
    check(size && size[0] === 641 && size[1] === 400, `${path.basename(file)} is a 641×400 PNG (${size})`);
  }
  const video = spawnSync(process.execPath, [snapshot, recordingDir, '--mp4', mp4, '--width', '320', '--height', '200'],
    { encoding: 'utf8' });
  process.stdout.write(video.stdout);
  process.stderr.write(video.stderr);
  check(video.status === 0, `snapshot --mp4 exits 0 (got ${video.status})`);
  const probe = spawnSync('ffprobe', ['-v', 'error', '-count_frames', '-select_streams', 'v:0', '-show_entries',
    'stream=codec_name,width,height,nb_read_frames,r_frame_rate', '-of', 'json', mp4], { encoding: 'utf8' });
  const stream = probe.status === 0 ? JSON.parse(probe.stdout).streams?.[0] : null;
  check(stream?.codec_name === 'h264', `video is H.264 (${stream?.codec_name})`);
  check(Number(stream?.nb_read_frames) === header.frame_count, `video has ${header.frame_count} frames (${stream?.nb_read_frames})`);
  check(stream?.width === 320 && stream?.height === 200, `video is 320×200 (${stream?.width}×${stream?.height})`);
  check(stream?.r_frame_rate === `${header.frame_rate}/1`, `video plays at the recording's ${header.frame_rate} fps (${stream?.r_frame_rate})`);

  // Bad input is refused with a clear message and a non-zero status.
  const bad = spawnSync(process.execPath, [snapshot, recordingDir, '--frames', `0,${last + 1}`, '--png', png],
    { encoding: 'utf8' });
  check(bad.status !== 0 && bad.stderr.includes(`${last + 1} not in the recording`), `an out-of-range frame is refused: ${bad.stderr.trim()}`);

  console.log(failures.length ? `${failures.length} check(s) failed` : 'all checks passed');
  return failures.length ? 1 : 0;
}

main().then((code) => process.exit(code), (e) => {
  console.error(`check_snapshot.mjs: ${e.stack ?? e.message}`);
  process.exit(1);
});

#pragma once
/// Launches the web viewer (viewer/serve.mjs) and headless snapshots (viewer/snapshot.mjs)
/// with Node.js, for `dexcloth view` and `dexcloth snapshot`.
#include <filesystem>
#include <string>
#include <vector>

namespace dexcloth::io {

/// The viewer folder: $DEXCLOTH_VIEWER_DIR if set, else the source tree's viewer/ (compiled in).
std::filesystem::path viewer_dir();

/// Serves the recording in `dir` on http://127.0.0.1:`port`/ (port 0 picks a free port) and
/// prints the URL; runs until the server stops (Ctrl-C) and returns its exit status.
/// Throws std::runtime_error, before starting anything, if the recording cannot be read or
/// node or the viewer's node_modules are missing (the message says to run scripts/setup.sh).
int run_viewer_server(const std::string& dir, int port);

/// Renders the recording in `dir` in headless Chromium: one PNG per frame in `frames` into
/// `png_dir` (skipped when `png_dir` is empty), and, when `mp4` is not empty, an H.264 video
/// of `frames` (all frames when `frames` is empty) encoded with ffmpeg. Returns the exit
/// status of the snapshot script (0 on success). Throws std::runtime_error, before starting
/// anything, for an unreadable recording, a frame not in it, or missing node, node_modules,
/// Chromium or (with `mp4`) ffmpeg.
int run_snapshot(const std::string& dir, const std::vector<int>& frames, const std::string& png_dir,
                 const std::string& mp4);

}  // namespace dexcloth::io

#pragma once
// Turns a run's PNG frames into an MP4 with ffmpeg when ffmpeg is installed (it is an optional
// extra: without it, or when it fails, the run still succeeds and only the frames are there).

#include <filesystem>
#include <ostream>
#include <string>

namespace sph {

// The ffmpeg executable on PATH, or empty.
std::filesystem::path find_ffmpeg();

// Encodes png/<prefix>_%05d.png (starting at `first_frame`) in `run_dir` at `fps` frames per
// second into run_dir/<prefix>.mp4. Returns false (after telling `log`) when ffmpeg is missing
// or fails; a failed encoding leaves no file behind.
bool encode_animation(const std::filesystem::path& run_dir, const std::string& prefix,
                      int first_frame, double fps, std::ostream* log);

}  // namespace sph

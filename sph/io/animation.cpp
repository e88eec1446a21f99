#include "sph/io/animation.h"

#include <cstdlib>
#include <sstream>
#include <system_error>

namespace sph {

namespace fs = std::filesystem;

fs::path find_ffmpeg() {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (dir.empty()) continue;
    const fs::path candidate = fs::path(dir) / "ffmpeg";
    std::error_code ec;
    const auto status = fs::status(candidate, ec);
    if (!ec && fs::is_regular_file(status) &&
        (status.permissions() & fs::perms::owner_exec) != fs::perms::none)
      return candidate;
  }
  return {};
}

namespace {

// Single quotes for the shell, with any single quote inside escaped.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

bool encode_animation(const fs::path& run_dir, const std::string& prefix, int first_frame,
                      double fps, std::ostream* log) {
  const fs::path ffmpeg = find_ffmpeg();
  if (ffmpeg.empty()) {
    if (log)
      *log << "ffmpeg is not installed: no " << prefix << ".mp4 (the PNG frames are in png/)\n";
    return false;
  }
  const fs::path out = run_dir / (prefix + ".mp4");
  std::ostringstream cmd;
  // Even width and height, as H.264 in yuv420p requires.
  cmd << quoted(ffmpeg.string()) << " -loglevel error -y -framerate " << fps << " -start_number "
      << first_frame << " -i " << quoted((run_dir / "png" / (prefix + "_%05d.png")).string())
      << " -vf 'scale=trunc(iw/2)*2:trunc(ih/2)*2' -pix_fmt yuv420p " << quoted(out.string());
  const int status = std::system(cmd.str().c_str());
  if (status != 0 || !fs::exists(out)) {
    std::error_code ec;
    fs::remove(out, ec);
    if (log) *log << "ffmpeg failed (status " << status << "): no " << prefix << ".mp4\n";
    return false;
  }
  return true;
}

}  // namespace sph

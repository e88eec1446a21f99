#include "common/checked_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>

namespace common {

namespace {

// The reason of the last failed stream operation, e.g. "No space left on device".
std::string reason() {
  return errno != 0 ? std::strerror(errno) : "write failed";
}

}  // namespace

void write_file_atomically(const std::filesystem::path& file, const std::string& content) {
  const std::filesystem::path tmp = file.string() + ".tmp";
  errno = 0;
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (out) out.write(content.data(), std::streamsize(content.size()));
  if (out) out.flush();
  out.close();
  std::error_code ec;
  if (!out) {
    const std::string why = reason();
    std::filesystem::remove(tmp, ec);
    throw WriteError(file.string() + ": cannot write (" + why + ")");
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw WriteError(file.string() + ": cannot write (" + ec.message() + ")");
  }
}

void append_to_file(const std::filesystem::path& file, const std::string& content) {
  errno = 0;
  std::ofstream out(file, std::ios::binary | std::ios::app);
  if (out) out.write(content.data(), std::streamsize(content.size()));
  if (out) out.flush();
  out.close();
  if (!out) throw WriteError(file.string() + ": cannot append (" + reason() + ")");
}

std::string read_whole_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot be read");
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw std::runtime_error(file.string() + ": reading failed");
  return content;
}

}  // namespace common

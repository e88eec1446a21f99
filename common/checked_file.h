#pragma once
// Writes that fail loudly. On a full disk, unchecked streams once left config.json and log.csv
// empty with exit 0; every file we write goes through these, or checks its stream the same way.
//  - write_file_atomically: the file appears whole or not at all (a temporary beside it, then a
//    rename); on failure the temporary is removed and WriteError names the file.
//  - append_to_file: appends and flushes, so a failed append is seen at once.
// WriteError is not an input error: the command exits 1 (common/exit_codes.h).

#include <filesystem>
#include <stdexcept>
#include <string>

namespace common {

class WriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void write_file_atomically(const std::filesystem::path& file, const std::string& content);

void append_to_file(const std::filesystem::path& file, const std::string& content);

// The whole content of `file`, bytes as they are; throws std::runtime_error naming the file when
// it cannot be read.
std::string read_whole_file(const std::filesystem::path& file);

}  // namespace common

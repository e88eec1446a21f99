#pragma once
// An output folder that appears whole or not at all, and never takes anything that is not ours.
//
// Everything is written into a hidden staging folder beside the target (`.NAME.partial-PID`).
// commit() moves an earlier result aside, renames the staging folder into place and only then
// deletes the earlier result, so a failed run never costs the previous one. Destruction without
// commit() removes the staging folder.
//
// An existing target is replaced only when the caller allows it (`--force`) and it is recognised
// as a folder of ours by its marker files. Whatever the caller allows, the current folder, any
// folder above it, the file system root, the home folder and folders that hold one of the
// caller's inputs are refused: `--out . --force` once deleted a user's working folder.
// Staging folders left by processes that died (kill -9, power loss) are removed when the next
// output folder is made beside them.

#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/exit_codes.h"

namespace common {

// A user error about an output path (exit code 2, like a config error).
class OutputPathError : public InputError {
 public:
  using InputError::InputError;
};

// `given` made absolute and lexically normal, without a trailing separator ("runs/new/" ->
// "/cwd/runs/new"). Throws OutputPathError for an empty path.
std::filesystem::path normalise_output_path(const std::string& given);

struct OutputFolderPolicy {
  std::string option = "--out";  // how the user named the path, for messages
  // Files that every folder written by this command holds; an existing target must hold all.
  std::vector<std::string> markers;
  bool replace = false;  // replace an existing target of ours (--force); else refuse it
  // The command's inputs (scene file, dataset folder, checkpoint): the target may not hold one.
  std::vector<std::filesystem::path> inputs;
  std::ostream* log = nullptr;  // where removed stale staging folders are reported
};

class OutputFolder {
 public:
  // Checks the target and makes the staging folder. Throws OutputPathError naming the option.
  OutputFolder(const std::string& given, OutputFolderPolicy policy);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::filesystem::path& target() const { return target_; }
  // Where to write: renamed to target() by commit().
  const std::filesystem::path& staging() const { return staging_; }
  // Puts the staged result in place of the target; the earlier target is deleted last.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

// For commands that write into their folder in place, resumably (spill-train's run folder,
// generate's dataset folder): checks, before their long work and without making anything, that
// `given` is a folder or can be made as one (its nearest existing ancestor is a folder this
// process may write into). Throws OutputPathError naming `option` (a raw "filesystem error"
// after the work, before).
void check_can_create(const std::string& given, const std::string& option);

// Removes `.*.partial-PID` and `.*.old-PID` folders in `parent` whose process no longer runs.
// Returns the removed paths.
std::vector<std::filesystem::path> remove_stale_staging(const std::filesystem::path& parent);

}  // namespace common

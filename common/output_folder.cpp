#include "common/output_folder.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

namespace common {
namespace fs = std::filesystem;

namespace {

// The path with symbolic links resolved as far as it exists, for comparisons.
fs::path resolved(const fs::path& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal() : r;
}

// True when `folder` is `path` or one of the folders above it.
bool contains(const fs::path& folder, const fs::path& path) {
  for (fs::path p = path;; p = p.parent_path()) {
    if (p == folder) return true;
    if (p == p.parent_path()) return false;
  }
}

std::string quoted(const fs::path& p) {
  return "\"" + p.string() + "\"";
}

// The PID at the end of a staging or set-aside folder's name, or -1 when it is not one of ours.
long staging_pid(const std::string& name) {
  if (name.size() < 2 || name[0] != '.') return -1;
  for (const char* tag : {".partial-", ".old-"}) {
    const auto at = name.rfind(tag);
    if (at == std::string::npos || at == 0) continue;
    const std::string digits = name.substr(at + std::char_traits<char>::length(tag));
    if (digits.empty() || digits.size() > 9 ||
        digits.find_first_not_of("0123456789") != std::string::npos)
      continue;
    return std::stol(digits);
  }
  return -1;
}

bool process_runs(long pid) {
  return ::kill(pid_t(pid), 0) == 0 || errno == EPERM;
}

}  // namespace

fs::path normalise_output_path(const std::string& given) {
  if (given.empty()) throw OutputPathError("empty output path");
  fs::path p = fs::absolute(fs::path(given)).lexically_normal();
  // "runs/new/" and "runs/new/." name the folder "runs/new".
  while (p.has_relative_path() && p.filename().empty()) p = p.parent_path();
  return p;
}

std::vector<fs::path> remove_stale_staging(const fs::path& parent) {
  std::vector<fs::path> removed;
  std::error_code ec;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    const long pid = staging_pid(it->path().filename().string());
    if (pid <= 0 || pid == long(::getpid()) || process_runs(pid)) continue;
    if (!it->is_directory(ec)) continue;
    std::error_code remove_error;
    fs::remove_all(it->path(), remove_error);
    if (!remove_error) removed.push_back(it->path());
  }
  return removed;
}

void check_can_create(const std::string& given, const std::string& option) {
  const fs::path target = normalise_output_path(given);
  auto refuse = [&](const std::string& why) {
    throw OutputPathError(option + " " + given + ": cannot create: " + why);
  };
  fs::path existing = target;
  std::error_code ec;
  while (!fs::exists(existing, ec) && existing.has_relative_path())
    existing = existing.parent_path();
  if (!fs::is_directory(existing, ec))
    refuse(quoted(existing) + (existing == target ? " exists and" : "") + " is not a folder");
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    refuse(quoted(existing) + " is not writable by this user");
}

OutputFolder::OutputFolder(const std::string& given, OutputFolderPolicy policy) {
  const std::string& option = policy.option;
  target_ = normalise_output_path(given);
  auto refuse = [&](const std::string& why) {
    throw OutputPathError(option + " " + given + ": " + why);
  };
  const fs::path real = resolved(target_);
  if (!real.has_relative_path()) refuse("refusing to write over the file system root");
  std::error_code ec;
  const fs::path cwd = resolved(fs::current_path(ec));
  if (!ec && contains(real, cwd))
    refuse("refusing the current folder or a folder above it (" + quoted(cwd) +
           "); name a new folder");
  if (const char* home = std::getenv("HOME"); home && *home && real == resolved(home))
    refuse("refusing the home folder; name a new folder");
  for (const fs::path& input : policy.inputs)
    if (!input.empty() && contains(real, resolved(fs::absolute(input))))
      refuse("holds the input " + quoted(input) + "; name a folder of outputs only");

  if (fs::exists(target_)) {
    if (!fs::is_directory(target_)) refuse("exists and is not a folder");
    if (!fs::is_empty(target_)) {
      if (!policy.replace) refuse("already exists (use --force to replace it)");
      for (const std::string& marker : policy.markers)
        if (!fs::exists(target_ / marker))
          refuse("exists and is not an output folder of this command (it has no " + marker +
                 "); refusing to replace it");
    }
  }

  const fs::path parent = target_.parent_path();
  fs::create_directories(parent, ec);
  if (ec) refuse("cannot create " + quoted(parent) + ": " + ec.message());
  for (const fs::path& stale : remove_stale_staging(parent))
    if (policy.log)
      *policy.log << "removed " << stale.string() << ", left by a run that did not finish\n";
  staging_ =
      parent / ("." + target_.filename().string() + ".partial-" + std::to_string(long(::getpid())));
  fs::remove_all(staging_, ec);
  fs::create_directories(staging_, ec);
  if (ec) refuse("cannot create " + quoted(staging_) + ": " + ec.message());
}

OutputFolder::~OutputFolder() {
  std::error_code ec;
  if (!committed_) fs::remove_all(staging_, ec);
}

void OutputFolder::commit() {
  std::error_code ec;
  const fs::path aside = target_.parent_path() / ("." + target_.filename().string() + ".old-" +
                                                  std::to_string(long(::getpid())));
  const bool had_target = fs::exists(target_);
  if (had_target) {
    fs::remove_all(aside, ec);
    fs::rename(target_, aside, ec);
    if (ec)
      throw std::runtime_error("cannot move the earlier " + target_.string() +
                               " aside: " + ec.message());
  }
  fs::rename(staging_, target_, ec);
  if (ec) {
    std::error_code restore;
    if (had_target) fs::rename(aside, target_, restore);
    throw std::runtime_error("cannot rename " + staging_.string() + " to " + target_.string() +
                             ": " + ec.message());
  }
  committed_ = true;
  if (had_target) fs::remove_all(aside, ec);
}

}  // namespace common

#include "tests/fuzz/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <thread>

namespace fuzz {

ChildOutcome run_child(const std::vector<std::string>& argv, const std::filesystem::path& log,
                       double timeout_s, double memory_bytes) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    setpgid(0, 0);  // its own group: a timeout kills the command and anything it started
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    rlimit limit{rlim_t(memory_bytes), rlim_t(memory_bytes)};
    setrlimit(RLIMIT_DATA, &limit);
    setenv("OMP_NUM_THREADS", "1", 1);
    setenv("OPENBLAS_NUM_THREADS", "1", 1);
    execv(args[0], args.data());
    _exit(127);
  }
  ChildOutcome out;
  int status = 0;
  for (;;) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (done == pid) break;
    if (out.seconds > timeout_s) {
      kill(-pid, SIGKILL);
      waitpid(pid, &status, 0);
      out.kind = ChildOutcome::Kind::kTimedOut;
      return out;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (WIFSIGNALED(status)) {
    out.kind = ChildOutcome::Kind::kSignalled;
    out.code = WTERMSIG(status);
  } else {
    out.code = WEXITSTATUS(status);
  }
  return out;
}

std::string describe(const ChildOutcome& o) {
  switch (o.kind) {
    case ChildOutcome::Kind::kExited:
      return "exit " + std::to_string(o.code);
    case ChildOutcome::Kind::kSignalled:
      return "signal " + std::to_string(o.code);
    case ChildOutcome::Kind::kTimedOut:
      return "timeout after " + std::to_string(int(o.seconds)) + " s";
  }
  return "";
}

}  // namespace fuzz

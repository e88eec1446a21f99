#include "train/data_parallel.h"

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

#include "common/exit_codes.h"

#ifdef SPILL_HAVE_GLOO
#include <torch/csrc/distributed/c10d/PrefixStore.hpp>
#include <torch/csrc/distributed/c10d/ProcessGroupGloo.hpp>
#include <torch/csrc/distributed/c10d/TCPStore.hpp>
#endif

namespace train {

namespace {

const char* variable(const char* name) {
  const char* v = std::getenv(name);
  return v && *v ? v : nullptr;
}

int whole_number(const char* name, const char* text) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (*end != '\0' || v < 0 || v > 1 << 30)
    throw common::InputError(std::string(name) + "=" + text + ": expected a whole number >= 0");
  return int(v);
}

}  // namespace

LaunchEnvironment read_launch_environment() {
  LaunchEnvironment e;
  if (variable("WORLD_SIZE") || variable("RANK")) {
    e.launcher = "torchrun";
    if (!variable("WORLD_SIZE") || !variable("RANK"))
      throw common::InputError(std::string(variable("RANK") ? "WORLD_SIZE" : "RANK") +
                               " is not set beside " + (variable("RANK") ? "RANK" : "WORLD_SIZE") +
                               ": a distributed launch sets both (torchrun does)");
    e.rank = whole_number("RANK", variable("RANK"));
    e.world = whole_number("WORLD_SIZE", variable("WORLD_SIZE"));
    if (variable("LOCAL_RANK")) e.local_rank = whole_number("LOCAL_RANK", variable("LOCAL_RANK"));
    const char* agent = variable("TORCHELASTIC_USE_AGENT_STORE");
    e.agent_store = agent && std::string(agent) == "True";
    if (variable("TORCHELASTIC_RESTART_COUNT"))
      e.restart =
          whole_number("TORCHELASTIC_RESTART_COUNT", variable("TORCHELASTIC_RESTART_COUNT"));
  } else if (variable("SLURM_NTASKS") && variable("SLURM_PROCID") &&
             whole_number("SLURM_NTASKS", variable("SLURM_NTASKS")) > 1) {
    e.launcher = "slurm";
    e.rank = whole_number("SLURM_PROCID", variable("SLURM_PROCID"));
    e.world = whole_number("SLURM_NTASKS", variable("SLURM_NTASKS"));
    if (variable("SLURM_LOCALID"))
      e.local_rank = whole_number("SLURM_LOCALID", variable("SLURM_LOCALID"));
  }
  if (e.world < 1) throw common::InputError("WORLD_SIZE=0: expected at least 1");
  if (e.rank >= e.world)
    throw common::InputError("RANK=" + std::to_string(e.rank) +
                             " is not below WORLD_SIZE=" + std::to_string(e.world));
  if (e.world > 1) {
    // The store listens on the address given, without authentication: no default address.
    if (!variable("MASTER_ADDR"))
      throw common::InputError(
          "MASTER_ADDR is not set: a distributed launch (" + e.launcher + ", world of " +
          std::to_string(e.world) +
          ") needs the address of rank 0's store, on a private network (torchrun sets it)");
    if (!variable("MASTER_PORT"))
      throw common::InputError(
          "MASTER_PORT is not set: a distributed launch needs the port of "
          "rank 0's store (torchrun sets it)");
    e.master_addr = variable("MASTER_ADDR");
    e.master_port = whole_number("MASTER_PORT", variable("MASTER_PORT"));
    if (e.master_port < 1 || e.master_port > 65535)
      throw common::InputError("MASTER_PORT=" + std::to_string(e.master_port) +
                               ": not a port (1-65535)");
  }
  return e;
}

#ifdef SPILL_HAVE_GLOO

struct DataParallel::Group {
  c10::intrusive_ptr<c10d::ProcessGroupGloo> pg;
  c10::intrusive_ptr<c10d::Store> store;  // kept for the roll call after a failed collective
};

namespace {

// LibTorch's message without the C++ backtrace it appends (a user reads the first line).
std::string message_of(const std::exception& e) {
  const auto* c10_error = dynamic_cast<const c10::Error*>(&e);
  std::string text = c10_error ? c10_error->what_without_backtrace() : e.what();
  const size_t trace = text.find("\nException raised from");
  if (trace != std::string::npos) text.resize(trace);
  if (text.size() > 300) text = text.substr(0, 300) + "...";
  return text;
}

// How long the ranks that are left wait for each other's answer after a collective failed.
constexpr std::chrono::milliseconds kRollCallWait{5000};

// After a failed collective: each rank still running writes its name to the store and looks
// for the others' for a few seconds; those that never answer are named. A rank that cannot
// reach the store names rank 0, whose process holds it.
std::string roll_call(c10d::Store& store, int rank, int world) {
  try {
    store.set("roll_call/" + std::to_string(rank), std::vector<uint8_t>{1});
    const auto deadline = std::chrono::steady_clock::now() + kRollCallWait;
    std::vector<int> silent;
    do {
      silent.clear();
      for (int r = 0; r < world; ++r)
        if (r != rank && !store.check({"roll_call/" + std::to_string(r)})) silent.push_back(r);
      if (silent.empty()) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    } while (std::chrono::steady_clock::now() < deadline);
    if (silent.empty()) return "every rank still answers (the network?)";
    std::string names;
    for (int r : silent) names += (names.empty() ? "" : ", ") + std::to_string(r);
    return (silent.size() == 1 ? "rank " : "ranks ") + names + " did not answer within " +
           std::to_string(kRollCallWait.count() / 1000) + " s (stopped, or stuck behind the one " +
           "that did)";
  } catch (const std::exception&) {
    return "rank 0, whose process holds the ranks' store, stopped (the store cannot be reached)";
  }
}

}  // namespace

std::unique_ptr<DataParallel> DataParallel::connect(const LaunchEnvironment& launch,
                                                    std::chrono::milliseconds timeout) {
  // Gloo writes to its sockets with writev and expects EPIPE when a peer has died; a C++
  // process left at SIGPIPE's default dies of the signal instead, silently, before the
  // collective can fail and name this rank (Python, and so torchrun's Python jobs, ignore
  // SIGPIPE at start-up). Only ranks get here: a single process keeps the default.
  std::signal(SIGPIPE, SIG_IGN);
  c10d::TCPStoreOptions o;
  o.port = std::uint16_t(launch.master_port);
  o.isServer = launch.rank == 0 && !launch.agent_store;
  if (!launch.agent_store) o.numWorkers = std::size_t(launch.world);
  // Gloo's connections wait for the other ranks (within the same deadline); the store's own
  // wait for its workers ran past it by seconds.
  o.waitWorkers = false;
  o.timeout = timeout;
  c10::intrusive_ptr<c10d::Store> store;
  // One deadline for joining: the store's wait for the other ranks and Gloo's connections
  // share it (each waited the whole timeout: 32 s for 15).
  const auto start = std::chrono::steady_clock::now();
  try {
    auto tcp = c10::make_intrusive<c10d::TCPStore>(launch.master_addr, o);
    store = tcp;
    if (launch.agent_store)
      store = c10::make_intrusive<c10d::PrefixStore>(
          "/worker/attempt_" + std::to_string(launch.restart), store);
    auto options = c10d::ProcessGroupGloo::Options::create();
    options->timeout = timeout;
    // Loopback on one machine; else GLOO_SOCKET_IFNAME's interface, as PyTorch takes it, or
    // the one this host's name resolves to.
    const char* interface = variable("GLOO_SOCKET_IFNAME");
    if (launch.master_addr == "127.0.0.1" || launch.master_addr == "localhost")
      options->devices.push_back(c10d::ProcessGroupGloo::createDeviceForHostname("127.0.0.1"));
    else if (interface)
      options->devices.push_back(c10d::ProcessGroupGloo::createDeviceForInterface(interface));
    else
      options->devices.push_back(c10d::ProcessGroupGloo::createDefaultDevice());
    const auto spent = std::chrono::duration_cast<std::chrono::milliseconds>(
        std::chrono::steady_clock::now() - start);
    if (spent >= timeout) throw std::runtime_error("the other ranks did not join");
    tcp->setTimeout(timeout - spent);
    auto group = std::make_unique<Group>();
    group->pg =
        c10::make_intrusive<c10d::ProcessGroupGloo>(store, launch.rank, launch.world, options);
    tcp->setTimeout(timeout);
    group->store = store;
    return std::unique_ptr<DataParallel>(
        new DataParallel(launch.rank, launch.world, std::move(group)));
  } catch (const std::exception& e) {
    throw std::runtime_error("rank " + std::to_string(launch.rank) + " of " +
                             std::to_string(launch.world) + ": cannot join the process group at " +
                             launch.master_addr + ":" + std::to_string(launch.master_port) +
                             " within " + std::to_string(timeout.count() / 1000) +
                             " s: " + message_of(e));
  }
}

void DataParallel::run(const char* what, const std::function<void()>& collective) {
  try {
    collective();
  } catch (const std::exception& e) {
    // Gloo names the peer's address, not its rank: the roll call finds which rank is gone. A
    // peer that died closes its connections, one that hangs runs into the timeout.
    throw std::runtime_error("rank " + std::to_string(rank_) + " of " + std::to_string(world_) +
                             ": the " + what + " with the other ranks failed: " +
                             roll_call(*group_->store, rank_, world_) + "; " + message_of(e));
  }
}

void DataParallel::sum(std::vector<double>& values) {
  if (values.empty()) return;
  std::vector<at::Tensor> t{torch::tensor(values, torch::kFloat64)};
  run("sum", [&] { group_->pg->allreduce(t)->wait(); });
  auto a = t[0].accessor<double, 1>();
  for (size_t k = 0; k < values.size(); ++k) values[k] = a[int64_t(k)];
}

void DataParallel::sum_weighted_gradients(const std::vector<torch::Tensor>& parameters,
                                          double weight) {
  torch::NoGradGuard no_grad;
  std::vector<torch::Tensor> grads;
  for (const auto& p : parameters)
    if (p.grad().defined()) grads.push_back(p.grad());
  size_t k = 0;
  while (k < grads.size()) {
    // One bucket: consecutive gradients up to kBucketBytes (at least one).
    size_t end = k;
    int64_t bytes = 0;
    while (end < grads.size() &&
           (end == k || bytes + grads[end].numel() * grads[end].element_size() <= kBucketBytes))
      bytes += grads[end].numel() * grads[end].element_size(), ++end;
    std::vector<torch::Tensor> flat_parts;
    for (size_t i = k; i < end; ++i) flat_parts.push_back(grads[i].reshape(-1));
    std::vector<at::Tensor> bucket{torch::cat(flat_parts).mul_(weight)};
    run("gradient allreduce", [&] { group_->pg->allreduce(bucket)->wait(); });
    int64_t offset = 0;
    for (size_t i = k; i < end; ++i) {
      const int64_t n = grads[i].numel();
      grads[i].copy_(bucket[0].slice(0, offset, offset + n).view_as(grads[i]));
      offset += n;
    }
    k = end;
  }
}

void DataParallel::broadcast_from_first(const std::vector<torch::Tensor>& tensors) {
  torch::NoGradGuard no_grad;
  for (const auto& t : tensors) {
    std::vector<at::Tensor> one{t.contiguous()};
    run("broadcast", [&] { group_->pg->broadcast(one)->wait(); });
    if (!one[0].is_same(t)) t.copy_(one[0]);
  }
}

double DataParallel::time_allreduce(int64_t floats, int repeats) {
  std::vector<at::Tensor> t{torch::ones({floats})};
  std::vector<double> seconds;
  for (int r = 0; r < repeats + 1; ++r) {
    std::vector<double> barrier{0};
    sum(barrier);  // start together
    const auto start = std::chrono::steady_clock::now();
    run("allreduce", [&] { group_->pg->allreduce(t)->wait(); });
    if (r > 0)  // the first warms the connections up
      seconds.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  return seconds[seconds.size() / 2];
}

#else  // without Gloo's headers: a single process only

struct DataParallel::Group {};

std::unique_ptr<DataParallel> DataParallel::connect(const LaunchEnvironment& launch,
                                                    std::chrono::milliseconds) {
  throw common::InputError(
      "a distributed launch (" + launch.launcher + ", world of " + std::to_string(launch.world) +
      ") needs spill-train built with c10d's Gloo: install libgloo-dev (scripts/setup.sh does) "
      "and build again");
}
void DataParallel::run(const char*, const std::function<void()>& collective) {
  collective();
}
void DataParallel::sum(std::vector<double>&) {}
void DataParallel::sum_weighted_gradients(const std::vector<torch::Tensor>&, double) {}
void DataParallel::broadcast_from_first(const std::vector<torch::Tensor>&) {}
double DataParallel::time_allreduce(int64_t, int) {
  return 0;
}

#endif

DataParallel::DataParallel(int rank, int world, std::unique_ptr<Group> group)
    : rank_(rank), world_(world), group_(std::move(group)) {}

DataParallel::~DataParallel() = default;

}  // namespace train

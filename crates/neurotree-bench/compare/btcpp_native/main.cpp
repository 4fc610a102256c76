// tree1111 (corpus/bench/tree1111.xml) with BehaviorTree.CPP built natively, measured as
// NeuroTree's `compare_native` example measures itself:
//
// - load: from the XML text to a tickable tree (`createTreeFromText`, with `Succ` and
//   `Fail` registered as simple conditions, as NeuroTree registers them), and its
//   destruction, so that every load starts from the same heap;
// - tick: `tickOnce()` on one tree, as NeuroTree's benchmarks call `tick_once` (no node of
//   this tree returns Running, so `tickExactlyOnce()` does the same); every tick visits all
//   1,111 nodes and the root succeeds (checked on every tick). Measured twice: with the
//   registered `Succ`/`Fail` conditions (the figure compared), and with the leaves replaced
//   by the built-in `AlwaysSuccess`/`AlwaysFailure` (`tick_builtin`, as `btcpp_tree1111.py`
//   runs it through behaviortreepy).
//
// - tick times: 100,000 ticks of the tree with `Succ`/`Fail`, each timed alone: p50, p99,
//   p99.9 and the slowest.
//
// Each is the fastest of ROUNDS rounds (default 300) of about 2 ms each (the number of
// ticks or loads per round is doubled from 1 until a round takes 2 ms): on a machine shared
// with other work, a round that nothing interrupted is what the code costs.
//
// Usage: btcpp_tree1111 TREE1111_XML [ROUNDS]
// Prints one JSON line per measure.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "behaviortree_cpp/bt_factory.h"

namespace {

constexpr double kNodesPerTick = 1111.0;
constexpr long kTimedTicks = 100000;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

// The fastest time per call of `f`, in seconds, over `rounds` rounds of about 2 ms.
template <typename F>
double fastest(long rounds, F&& f, long* per_round) {
  long n = 1;
  for (;;) {
    const auto start = std::chrono::steady_clock::now();
    for (long i = 0; i < n; ++i) f();
    if (seconds_since(start) >= 0.002 || n >= (1L << 30)) break;
    n *= 2;
  }
  double best = 1e30;
  for (long round = 0; round < rounds; ++round) {
    const auto start = std::chrono::steady_clock::now();
    for (long i = 0; i < n; ++i) f();
    const double per = seconds_since(start) / static_cast<double>(n);
    if (per < best) best = per;
  }
  *per_round = n;
  return best;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s TREE1111_XML [ROUNDS]\n", argv[0]);
    return 2;
  }
  std::ifstream file(argv[1]);
  if (!file) {
    std::fprintf(stderr, "cannot read %s\n", argv[1]);
    return 2;
  }
  std::stringstream text;
  text << file.rdbuf();
  const std::string xml = text.str();
  const long rounds = argc > 2 ? std::atol(argv[2]) : 300;

  BT::BehaviorTreeFactory factory;
  factory.registerSimpleCondition(
      "Succ", [](BT::TreeNode&) { return BT::NodeStatus::SUCCESS; });
  factory.registerSimpleCondition(
      "Fail", [](BT::TreeNode&) { return BT::NodeStatus::FAILURE; });

  long n = 0;
  const double per_load = fastest(
      rounds, [&] { auto tree = factory.createTreeFromText(xml); }, &n);
  std::printf("{\"name\":\"btcpp_native/load\",\"per_round\":%ld,\"us_per_load\":%.3f}\n", n,
              per_load * 1e6);

  const auto time_ticks = [&](const std::string& text, const char* name) {
    auto tree = factory.createTreeFromText(text);
    const double per_tick = fastest(
        rounds,
        [&] {
          if (tree.tickOnce() != BT::NodeStatus::SUCCESS) {
            std::fprintf(stderr, "tree1111: the root did not succeed\n");
            std::exit(1);
          }
        },
        &n);
    std::printf(
        "{\"name\":\"%s\",\"per_round\":%ld,\"ns_per_tick\":%.1f,\"ns_per_node\":%.3f}\n",
        name, n, per_tick * 1e9, per_tick * 1e9 / kNodesPerTick);
  };
  // Each tick timed alone, as NeuroTree's `compare_native` times its own: the percentiles a
  // control loop's period has to cover.
  const auto tick_times = [&](const std::string& text, const char* name) {
    auto tree = factory.createTreeFromText(text);
    std::vector<long long> nanos;
    nanos.reserve(kTimedTicks);
    for (long i = 0; i < kTimedTicks; ++i) {
      const auto start = std::chrono::steady_clock::now();
      const auto status = tree.tickOnce();
      const auto took = std::chrono::steady_clock::now() - start;
      if (status != BT::NodeStatus::SUCCESS) {
        std::fprintf(stderr, "tree1111: the root did not succeed\n");
        std::exit(1);
      }
      nanos.push_back(std::chrono::duration_cast<std::chrono::nanoseconds>(took).count());
    }
    std::sort(nanos.begin(), nanos.end());
    // Nearest rank, as NeuroTree's `TickTimes::percentiles`.
    const auto rank = [&](double q) {
      auto index = static_cast<size_t>(std::ceil(q * static_cast<double>(nanos.size())));
      index = std::max<size_t>(index, 1);
      return nanos[std::min(index, nanos.size()) - 1];
    };
    std::printf(
        "{\"name\":\"%s\",\"ticks\":%zu,\"p50_ns\":%lld,\"p99_ns\":%lld,\"p999_ns\":%lld,"
        "\"max_ns\":%lld}\n",
        name, nanos.size(), rank(0.50), rank(0.99), rank(0.999), nanos.back());
  };
  time_ticks(xml, "btcpp_native/tick");
  tick_times(xml, "btcpp_native/tick_times");
  std::string builtin = xml;
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"<Succ/>", "<AlwaysSuccess/>"},
                                 {"<Fail/>", "<AlwaysFailure/>"}}) {
    for (auto at = builtin.find(from); at != std::string::npos; at = builtin.find(from, at)) {
      builtin.replace(at, from.size(), to);
    }
  }
  time_ticks(builtin, "btcpp_native/tick_builtin");
  return 0;
}

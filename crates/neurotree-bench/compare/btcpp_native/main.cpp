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
// Usage: btcpp_tree1111 TREE1111_XML [TICKS] [LOADS]
// Prints one JSON line per measure.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "behaviortree_cpp/bt_factory.h"

namespace {

constexpr double kNodesPerTick = 1111.0;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s TREE1111_XML [TICKS] [LOADS]\n", argv[0]);
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
  const long ticks = argc > 2 ? std::atol(argv[2]) : 20000;
  const long loads = argc > 3 ? std::atol(argv[3]) : 200;

  BT::BehaviorTreeFactory factory;
  factory.registerSimpleCondition(
      "Succ", [](BT::TreeNode&) { return BT::NodeStatus::SUCCESS; });
  factory.registerSimpleCondition(
      "Fail", [](BT::TreeNode&) { return BT::NodeStatus::FAILURE; });

  // Loading: warm up, then the best of 5 rounds of `loads` loads each.
  for (int i = 0; i < 10; ++i) {
    auto tree = factory.createTreeFromText(xml);
  }
  double best_load = 1e30;
  for (int round = 0; round < 5; ++round) {
    const auto start = std::chrono::steady_clock::now();
    for (long i = 0; i < loads; ++i) {
      auto tree = factory.createTreeFromText(xml);
    }
    const double per_load = seconds_since(start) / static_cast<double>(loads);
    if (per_load < best_load) best_load = per_load;
  }
  std::printf("{\"name\":\"btcpp_native/load\",\"loads\":%ld,\"us_per_load\":%.3f}\n", loads,
              best_load * 1e6);

  // Ticking: warm up, then the best of 5 rounds of `ticks` ticks each.
  const auto time_ticks = [&](const std::string& text, const char* name) {
    auto tree = factory.createTreeFromText(text);
    double best_tick = 1e30;
    for (int round = 0; round < 6; ++round) {
      const long n = round == 0 ? ticks / 10 + 1 : ticks;
      const auto start = std::chrono::steady_clock::now();
      for (long i = 0; i < n; ++i) {
        if (tree.tickOnce() != BT::NodeStatus::SUCCESS) {
          std::fprintf(stderr, "tree1111: the root did not succeed\n");
          std::exit(1);
        }
      }
      const double per_tick = seconds_since(start) / static_cast<double>(n);
      if (round > 0 && per_tick < best_tick) best_tick = per_tick;
    }
    std::printf(
        "{\"name\":\"%s\",\"ticks\":%ld,\"ns_per_tick\":%.1f,"
        "\"ns_per_node\":%.3f}\n",
        name, ticks, best_tick * 1e9, best_tick * 1e9 / kNodesPerTick);
  };
  time_ticks(xml, "btcpp_native/tick");
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

// Scotch's graph partitioning (tissue/graph_partitioner.hpp); its error
// handler library libscotcherr prints Scotch's own message before a call
// fails.
#include "tissue/graph_partitioner.hpp"

// scotch.h uses FILE and the fixed-width integers without including their headers.
#include <cstdint>
#include <cstdio>
#include <scotch.h>

#include <stdexcept>
#include <string>
#include <type_traits>

namespace fibrodem {
namespace {

static_assert(std::is_same_v<SCOTCH_Num, int>, "the compressed graph's int arrays are handed to Scotch as they are");

// Seed of Scotch's random generator: any fixed number; fixed so that every
// rank (and every run) gets the same partition of the same tissue.
constexpr SCOTCH_Num kScotchSeed = 1;

void check(int status, const char* what) {
  if (status != 0) throw std::runtime_error(std::string("cell partition: Scotch's ") + what + " failed");
}

// Scotch's state for one partition, freed however the partition ends.
struct ScotchSession {
  SCOTCH_Context context;
  SCOTCH_Graph graph, bound_graph;
  SCOTCH_Strat strategy;
  bool context_made = false, graph_made = false, bound_made = false, strategy_made = false;
  ~ScotchSession() {
    if (bound_made) SCOTCH_graphExit(&bound_graph);
    if (graph_made) SCOTCH_graphExit(&graph);
    if (strategy_made) SCOTCH_stratExit(&strategy);
    if (context_made) SCOTCH_contextExit(&context);
  }
};

}  // namespace

std::vector<int> split_graph(const CompressedGraph& g, int parts, double imbalance) {
  const std::size_t n = g.row_start.size() - 1;
  ScotchSession s;
  // Deterministic mode and a fixed seed, on one thread: the same graph
  // gives the same parts on every rank and in every run.
  check(SCOTCH_contextInit(&s.context), "contextInit");
  s.context_made = true;
  check(SCOTCH_contextRandomClone(&s.context), "contextRandomClone");
  check(SCOTCH_contextOptionSetNum(&s.context, SCOTCH_OPTIONNUMDETERMINISTIC, 1), "deterministic option");
  check(SCOTCH_contextOptionSetNum(&s.context, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1), "fixed-seed option");
  SCOTCH_contextRandomSeed(&s.context, kScotchSeed);
  check(SCOTCH_contextThreadSpawn(&s.context, 1, nullptr), "contextThreadSpawn");

  // Scotch only reads the arrays it is given here.
  auto* row_start = const_cast<SCOTCH_Num*>(g.row_start.data());
  auto* neighbours = const_cast<SCOTCH_Num*>(g.neighbours.data());
  check(SCOTCH_graphInit(&s.graph), "graphInit");
  s.graph_made = true;
  const auto vertices = static_cast<SCOTCH_Num>(n);
  const auto arcs = static_cast<SCOTCH_Num>(g.neighbours.size());
  check(SCOTCH_graphBuild(&s.graph, 0, vertices, row_start, row_start + 1, nullptr, nullptr, arcs, neighbours,
                          nullptr),
        "graphBuild");
  check(SCOTCH_graphInit(&s.bound_graph), "graphInit");
  s.bound_made = true;
  check(SCOTCH_contextBindGraph(&s.context, &s.graph, &s.bound_graph), "contextBindGraph");

  // Quality over speed (set-up, once a run) and balance first; a fibrotic
  // tissue's graph may be disconnected.
  check(SCOTCH_stratInit(&s.strategy), "stratInit");
  s.strategy_made = true;
  check(SCOTCH_stratGraphMapBuild(&s.strategy, SCOTCH_STRATQUALITY | SCOTCH_STRATBALANCE | SCOTCH_STRATDISCONNECTED,
                                  parts, imbalance),
        "stratGraphMapBuild");
  std::vector<int> part(n, 0);
  check(SCOTCH_graphPart(&s.bound_graph, parts, &s.strategy, part.data()), "graphPart");
  return part;
}

}  // namespace fibrodem

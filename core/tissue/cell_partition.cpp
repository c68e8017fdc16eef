#include "tissue/cell_partition.hpp"

// scotch.h uses FILE and the fixed-width integers without including their headers.
#include <cstdint>
#include <cstdio>
#include <scotch.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace fibrodem {

namespace {

// Seed of Scotch's random generator: any fixed number; fixed so that every
// rank (and every run) gets the same partition of the same tissue.
constexpr SCOTCH_Num kScotchSeed = 1;

// The cell graph in compressed rows, each edge in both directions (Scotch's
// symmetric graph without loops; cell_edges are unique with i < j).
struct CompressedGraph {
  std::vector<SCOTCH_Num> row_start, neighbours;
};

CompressedGraph compressed_graph(const Tissue& tissue) {
  const std::size_t n = tissue.cell_count();
  CompressedGraph g;
  g.row_start.assign(n + 1, 0);
  for (const auto& edge : tissue.cell_edges) {
    ++g.row_start[static_cast<std::size_t>(edge.first) + 1];
    ++g.row_start[static_cast<std::size_t>(edge.second) + 1];
  }
  for (std::size_t cell = 0; cell < n; ++cell) g.row_start[cell + 1] += g.row_start[cell];
  g.neighbours.resize(static_cast<std::size_t>(g.row_start[n]));
  std::vector<SCOTCH_Num> next(g.row_start.begin(), g.row_start.end() - 1);
  for (const auto& edge : tissue.cell_edges) {
    g.neighbours[static_cast<std::size_t>(next[static_cast<std::size_t>(edge.first)]++)] = edge.second;
    g.neighbours[static_cast<std::size_t>(next[static_cast<std::size_t>(edge.second)]++)] = edge.first;
  }
  return g;
}

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

std::vector<std::size_t> CellPartition::sizes() const {
  std::vector<std::size_t> count(static_cast<std::size_t>(parts), 0);
  for (int part : part_of) ++count[static_cast<std::size_t>(part)];
  return count;
}

std::vector<int> CellPartition::cells_of(int part) const {
  std::vector<int> cells;
  for (std::size_t cell = 0; cell < part_of.size(); ++cell)
    if (part_of[cell] == part) cells.push_back(static_cast<int>(cell));
  return cells;
}

std::size_t CellPartition::cut_edges(const Tissue& tissue) const {
  std::size_t cut = 0;
  for (const auto& edge : tissue.cell_edges)
    cut += part_of[static_cast<std::size_t>(edge.first)] != part_of[static_cast<std::size_t>(edge.second)];
  return cut;
}

CellPartition partition_cells(const Tissue& tissue, int parts) {
  const std::size_t n = tissue.cell_count();
  if (parts < 1 || static_cast<std::size_t>(parts) > n)
    throw std::invalid_argument("cannot split " + std::to_string(n) + " cells into " + std::to_string(parts) +
                                " parts: expected 1 to " + std::to_string(n) + " parts (one per MPI rank)");
  CellPartition partition;
  partition.parts = parts;
  partition.part_of.assign(n, 0);
  if (parts == 1) return partition;

  const CompressedGraph g = compressed_graph(tissue);
  ScotchSession s;
  // Deterministic mode and a fixed seed, on one thread: the same tissue
  // gives the same parts on every rank and in every run.
  check(SCOTCH_contextInit(&s.context), "contextInit");
  s.context_made = true;
  check(SCOTCH_contextRandomClone(&s.context), "contextRandomClone");
  check(SCOTCH_contextOptionSetNum(&s.context, SCOTCH_OPTIONNUMDETERMINISTIC, 1), "deterministic option");
  check(SCOTCH_contextOptionSetNum(&s.context, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1), "fixed-seed option");
  SCOTCH_contextRandomSeed(&s.context, kScotchSeed);
  check(SCOTCH_contextThreadSpawn(&s.context, 1, nullptr), "contextThreadSpawn");

  check(SCOTCH_graphInit(&s.graph), "graphInit");
  s.graph_made = true;
  const auto vertices = static_cast<SCOTCH_Num>(n);
  const auto arcs = static_cast<SCOTCH_Num>(g.neighbours.size());
  check(SCOTCH_graphBuild(&s.graph, 0, vertices, g.row_start.data(), g.row_start.data() + 1, nullptr, nullptr, arcs,
                          g.neighbours.data(), nullptr),
        "graphBuild");
  check(SCOTCH_graphInit(&s.bound_graph), "graphInit");
  s.bound_made = true;
  check(SCOTCH_contextBindGraph(&s.context, &s.graph, &s.bound_graph), "contextBindGraph");

  // Quality over speed (set-up, once a run) and balance first; a fibrotic
  // tissue's graph may be disconnected.
  check(SCOTCH_stratInit(&s.strategy), "stratInit");
  s.strategy_made = true;
  check(SCOTCH_stratGraphMapBuild(&s.strategy, SCOTCH_STRATQUALITY | SCOTCH_STRATBALANCE | SCOTCH_STRATDISCONNECTED,
                                  parts, kPartImbalance),
        "stratGraphMapBuild");
  std::vector<SCOTCH_Num> part(n, 0);
  check(SCOTCH_graphPart(&s.bound_graph, parts, &s.strategy, part.data()), "graphPart");
  for (std::size_t cell = 0; cell < n; ++cell) partition.part_of[cell] = static_cast<int>(part[cell]);
  return partition;
}

}  // namespace fibrodem

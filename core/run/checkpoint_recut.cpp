#include "run/checkpoint_recut.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "run/checkpoint_dir.hpp"

namespace fibrodem {

CellPlaces::CellPlaces(const std::vector<std::vector<int>>& cells_of_part, std::size_t tissue_cells)
    : part_(tissue_cells, -1), index_(tissue_cells, -1) {
  for (std::size_t r = 0; r < cells_of_part.size(); ++r) {
    part_cells_.push_back(cells_of_part[r].size());
    for (std::size_t i = 0; i < cells_of_part[r].size(); ++i) {
      const int cell = cells_of_part[r][i];
      if (cell < 0 || static_cast<std::size_t>(cell) >= tissue_cells || part_[static_cast<std::size_t>(cell)] >= 0)
        throw CheckpointError("its parts list cell " + std::to_string(cell) +
                              (cell >= 0 && static_cast<std::size_t>(cell) < tissue_cells ? " twice" : ", which this tissue lacks"));
      part_[static_cast<std::size_t>(cell)] = static_cast<int>(r);
      index_[static_cast<std::size_t>(cell)] = static_cast<int>(i);
    }
  }
}

std::size_t CellPlaces::where(int cell, const std::string& name) const {
  if (cell < 0 || static_cast<std::size_t>(cell) >= part_.size() || part_[static_cast<std::size_t>(cell)] < 0)
    throw CheckpointError("no part of it holds cell " + std::to_string(cell) + " in '" + name + "'");
  return static_cast<std::size_t>(part_[static_cast<std::size_t>(cell)]);
}

void CellPlaces::check_parts(const std::vector<CheckpointFields>& parts) const {
  if (parts.size() != part_cells_.size())
    throw std::invalid_argument("CellPlaces: " + std::to_string(parts.size()) + " parts given for " +
                                std::to_string(part_cells_.size()) + " lists of cells");
}

std::vector<double> CellPlaces::rows(const std::vector<CheckpointFields>& parts, const std::string& name,
                                     const std::vector<int>& cells) const {
  check_parts(parts);
  std::vector<std::vector<double>> values;
  std::size_t row_count = 0;
  bool row_count_known = false;
  for (std::size_t r = 0; r < parts.size(); ++r) {
    values.push_back(part_cells_[r] > 0 || parts[r].has(name) ? parts[r].numbers(name) : std::vector<double>());
    if (part_cells_[r] == 0) continue;
    if (values[r].size() % part_cells_[r] != 0 || (row_count_known && values[r].size() / part_cells_[r] != row_count))
      throw CheckpointError("its field '" + name + "' has " + std::to_string(values[r].size()) + " values for " +
                            std::to_string(part_cells_[r]) + " cells in part " + std::to_string(r));
    row_count = values[r].size() / part_cells_[r];
    row_count_known = true;
  }
  const std::size_t n = cells.size();
  std::vector<double> out(row_count * n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = where(cells[i], name), j = static_cast<std::size_t>(index_[static_cast<std::size_t>(cells[i])]);
    for (std::size_t k = 0; k < row_count; ++k) out[k * n + i] = values[r][k * part_cells_[r] + j];
  }
  return out;
}

std::string CellPlaces::bytes(const std::vector<CheckpointFields>& parts, const std::string& name,
                              const std::vector<int>& cells) const {
  check_parts(parts);
  std::vector<std::string> values;
  std::size_t width = 0;
  for (std::size_t r = 0; r < parts.size(); ++r) {
    values.push_back(part_cells_[r] > 0 || parts[r].has(name) ? parts[r].text(name) : std::string());
    if (part_cells_[r] == 0) continue;
    if (values[r].size() % part_cells_[r] != 0 || (width > 0 && values[r].size() / part_cells_[r] != width))
      throw CheckpointError("its field '" + name + "' has " + std::to_string(values[r].size()) + " bytes for " +
                            std::to_string(part_cells_[r]) + " cells in part " + std::to_string(r));
    width = values[r].size() / part_cells_[r];
  }
  std::string out;
  out.reserve(width * cells.size());
  for (const int cell : cells) {
    const std::size_t r = where(cell, name), j = static_cast<std::size_t>(index_[static_cast<std::size_t>(cell)]);
    out.append(values[r], j * width, width);
  }
  return out;
}

long long ranks_of_checkpoint(const CheckpointFields& checkpoint) {
  return checkpoint.has("run.mpi_ranks") ? checkpoint.integer("run.mpi_ranks") : 1;
}

CheckpointFields read_checkpoint_part(const std::filesystem::path& file, const CheckpointFields& checkpoint, int rank) {
  const long long ranks = ranks_of_checkpoint(checkpoint);
  const std::filesystem::path part_file = rank_checkpoint_path(file, rank);
  CheckpointFields part;
  try {
    part = read_checkpoint_file(part_file);
  } catch (const CheckpointError& e) {
    throw CheckpointError(fmt::format("checkpoint {}: rank {}'s part cannot be read: {}", file.string(), rank, e.what()));
  }
  if (!part.has("run.mpi_rank") || part.integer("run.mpi_rank") != rank || ranks_of_checkpoint(part) != ranks ||
      part.number("run.time_ms") != checkpoint.number("run.time_ms"))
    throw CheckpointError(fmt::format("{} is not rank {} of {}'s part of the checkpoint at t = {:g} ms", part_file.string(),
                                      rank, ranks, checkpoint.number("run.time_ms")));
  return part;
}

std::vector<CheckpointFields> read_checkpoint_parts(const std::filesystem::path& file, CheckpointFields checkpoint) {
  const long long ranks = ranks_of_checkpoint(checkpoint);
  std::vector<CheckpointFields> parts;
  parts.reserve(static_cast<std::size_t>(ranks));
  parts.push_back(std::move(checkpoint));
  for (int rank = 1; rank < ranks; ++rank) parts.push_back(read_checkpoint_part(file, parts.front(), rank));
  return parts;
}

std::vector<std::vector<int>> own_cells_of_parts(const std::vector<CheckpointFields>& parts) {
  std::vector<std::vector<int>> own;
  for (const auto& part : parts) {
    std::vector<int> cells;
    for (const auto& name : part.names_starting("ionic."))
      if (name.size() > 6 && name.compare(name.size() - 6, 6, ".cells") == 0) {
        const std::vector<int> more = part.ints(name);
        cells.insert(cells.end(), more.begin(), more.end());
      }
    std::sort(cells.begin(), cells.end());
    own.push_back(std::move(cells));
  }
  return own;
}

}  // namespace fibrodem

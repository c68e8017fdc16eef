#include "run/checkpoint_recut.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "run/checkpoint_dir.hpp"

namespace fibrodem {

CellPick::CellPick(const std::vector<int>& cells, std::size_t tissue_cells)
    : cells_(cells), place_(tissue_cells, -1), listed_(tissue_cells, 0), found_(cells.size(), 0) {
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (cells[i] < 0 || static_cast<std::size_t>(cells[i]) >= tissue_cells)
      throw std::invalid_argument("CellPick: cell " + std::to_string(cells[i]) + " picked from a tissue of " +
                                  std::to_string(tissue_cells));
    place_[static_cast<std::size_t>(cells[i])] = static_cast<int>(i);
  }
}

void CellPick::take(const CheckpointFields& part, int r, const std::vector<int>& part_cells,
                    const std::vector<std::string>& rows, const std::vector<std::string>& bytes) {
  // (j, i): the part's cell j is the i-th picked.
  std::vector<std::pair<std::size_t, std::size_t>> at;
  for (std::size_t j = 0; j < part_cells.size(); ++j) {
    const int cell = part_cells[j];
    if (cell < 0 || static_cast<std::size_t>(cell) >= place_.size())
      throw CheckpointError("its parts list cell " + std::to_string(cell) + ", which this tissue lacks");
    if (listed_[static_cast<std::size_t>(cell)]) throw CheckpointError("its parts list cell " + std::to_string(cell) + " twice");
    listed_[static_cast<std::size_t>(cell)] = 1;
    if (const int i = place_[static_cast<std::size_t>(cell)]; i >= 0) {
      at.emplace_back(j, static_cast<std::size_t>(i));
      found_[static_cast<std::size_t>(i)] = 1;
    }
  }
  // Every field named is put, empty where no part taken has cells for it
  // (a population this rank and the parts it read hold none of).
  for (const std::string& name : rows) rows_.try_emplace(name);
  for (const std::string& name : bytes) bytes_.try_emplace(name);
  const std::size_t n = part_cells.size();
  if (n == 0) return;  // (its fields, if it has them, are empty)
  const auto uneven = [&](const std::string& name, std::size_t size, const char* unit) {
    return CheckpointError("its field '" + name + "' has " + std::to_string(size) + " " + unit + " for " +
                           std::to_string(n) + " cells in part " + std::to_string(r));
  };
  for (const std::string& name : rows) {
    const std::vector<double> values = part.numbers(name);
    Rows& field = rows_[name];
    if (values.size() % n != 0 || (field.started && values.size() / n != field.rows))
      throw uneven(name, values.size(), "values");
    if (!field.started) field = {std::vector<double>(values.size() / n * picked()), values.size() / n, true};
    for (const auto& [j, i] : at)
      for (std::size_t k = 0; k < field.rows; ++k) field.values[k * picked() + i] = values[k * n + j];
  }
  for (const std::string& name : bytes) {
    const std::string values = part.text(name);
    auto& [out, width] = bytes_[name];
    if (values.size() % n != 0 || (width > 0 && values.size() / n != width)) throw uneven(name, values.size(), "bytes");
    if (width == 0) {
      width = values.size() / n;
      out.assign(width * picked(), '\0');
    }
    for (const auto& [j, i] : at) out.replace(i * width, width, values, j * width, width);
  }
}

void CellPick::check_complete(const std::string& name) const {
  for (std::size_t i = 0; i < found_.size(); ++i)
    if (!found_[i])
      throw CheckpointError("no part of it holds cell " + std::to_string(cells_[i]) + " in '" + name + "'");
}

void CellPick::put_into(CheckpointFields& out) const {
  for (const auto& [name, field] : rows_) {
    check_complete(name);
    out.put(name, field.values);
  }
  for (const auto& [name, field] : bytes_) {
    check_complete(name);
    out.put_text(name, field.first);
  }
}

std::vector<double> CellPick::release_rows(const std::string& name) {
  check_complete(name);
  return std::move(rows_[name].values);
}

bool CellPick::complete() const { return std::all_of(found_.begin(), found_.end(), [](char f) { return f != 0; }); }

int take_checkpoint_parts(const std::filesystem::path& file, const CheckpointFields& checkpoint,
                          const std::vector<int>& likely, const std::function<bool()>& complete,
                          const std::function<void(const CheckpointFields& part, int r)>& visit) {
  const long long ranks = ranks_of_checkpoint(checkpoint);
  std::vector<char> taken(static_cast<std::size_t>(ranks), 0);
  int read = 0;
  auto take = [&](int r) {
    if (r < 0 || r >= ranks || taken[static_cast<std::size_t>(r)]) return;
    taken[static_cast<std::size_t>(r)] = 1;
    ++read;
    if (r == 0) visit(checkpoint, 0);
    else visit(read_checkpoint_part(file, checkpoint, r), r);
  };
  take(0);
  for (const int r : likely) take(r);
  for (int r = 1; r < ranks && !complete(); ++r) take(r);
  return read;
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

std::vector<int> own_cells_of_part(const CheckpointFields& part) {
  std::vector<int> cells;
  for (const auto& name : part.names_starting("ionic."))
    if (name.size() > 6 && name.compare(name.size() - 6, 6, ".cells") == 0) {
      const std::vector<int> more = part.ints(name);
      cells.insert(cells.end(), more.begin(), more.end());
    }
  std::sort(cells.begin(), cells.end());
  return cells;
}

}  // namespace fibrodem

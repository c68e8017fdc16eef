// Removable singularities: N / (exp(E) - 1) or N / (1 - exp(E)) with N (or a
// factor of it) a multiple of E, 0/0 where E = 0 (the alpha_m of Hodgkin &
// Huxley and its many descendants). Rewritten as (N/E) * E/(exp(E) - 1) with
// N/E the ratio of their slopes in V and E/(exp(E) - 1) = exprel(-E)
// (model/simd.hpp), exact at and around E = 0.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellml/expression_writer.hpp"

namespace fibrodem::cellml {

class Singularities {
 public:
  Singularities(const Model& model, const InterfaceMap& boundary, ExpressionWriter& writer)
      : m_(model), b_(boundary), w_(writer) {}

  // The divide node e rewritten, or nullopt if it is not such a form.
  std::optional<Code> rewrite(const Expr& e);

  int count() const { return static_cast<int>(paths_.size()); }
  const std::vector<std::string>& paths() const { return paths_; }

 private:
  std::optional<std::string> derivative(const Expr& e);
  std::vector<double> sweep_V(const Expr& e) const;

  const Model& m_;
  const InterfaceMap& b_;
  ExpressionWriter& w_;
  std::vector<std::string> paths_;
};

}  // namespace fibrodem::cellml

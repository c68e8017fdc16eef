#include "coupling/coupling_region.hpp"

#include <cmath>

namespace fibrodem {

void read_span_mm(JsonReader& r, const std::string& key, double& min_um, double& max_um) {
  const json& span = r.raw(key);
  const std::string path = r.path_of(key);
  if (span.is_null()) throw ManifestError(path, "required: [min, max] in mm");
  if (!span.is_array() || span.size() != 2 || !span[0].is_number() || !span[1].is_number())
    throw ManifestError(path, "expected [min, max] in mm, got " + describe_json(span));
  const double lo = span[0].get<double>(), hi = span[1].get<double>();
  if (!(lo < hi) || std::abs(lo) > 1e6 || std::abs(hi) > 1e6)
    throw ManifestError(path, "expected min < max (within +-1e6 mm), got " + describe_json(span));
  min_um = lo * 1000;
  max_um = hi * 1000;
}

namespace {

CouplingRegion read_region(const json& object, const std::string& path, const JunctionConductances& base) {
  JsonReader r(object, path);
  CouplingRegion region;
  region.path = path;
  region.shape = r.text("shape", std::nullopt, {"rectangle", "ellipse"}) == "ellipse" ? CouplingRegion::Shape::ellipse
                                                                                       : CouplingRegion::Shape::rectangle;
  read_span_mm(r, "x_mm", region.x_min_um, region.x_max_um);
  read_span_mm(r, "y_mm", region.y_min_um, region.y_max_um);
  const bool sets = r.has("D_m_nS") || r.has("D_m_side_nS") || r.has("D_f_nS");
  if (r.has("scale") == sets)
    throw ManifestError(path, sets ? "expected either scale or conductances (D_m_nS, D_m_side_nS, D_f_nS), got both"
                                   : "expected scale or conductances (D_m_nS, D_m_side_nS, D_f_nS), got neither");
  if (sets) {
    JunctionConductances& g = region.g_nS;
    g.D_m_nS = r.number("D_m_nS", base.D_m_nS, 0.0, 1e9);
    g.D_m_side_nS = r.number("D_m_side_nS", r.has("D_m_nS") ? g.D_m_nS : base.D_m_side_nS, 0.0, 1e9);
    g.D_f_nS = r.number("D_f_nS", base.D_f_nS, 0.0, 1e9);
  } else {
    const double scale = r.number("scale", std::nullopt, 0.0, 1e6);
    region.g_nS = {base.D_m_nS * scale, base.D_m_side_nS * scale, base.D_f_nS * scale};
  }
  r.finish();
  return region;
}

}  // namespace

bool CouplingRegion::contains(double x_um, double y_um) const {
  if (shape == Shape::rectangle) return x_um >= x_min_um && x_um <= x_max_um && y_um >= y_min_um && y_um <= y_max_um;
  const double u = (2 * x_um - x_min_um - x_max_um) / (x_max_um - x_min_um);
  const double v = (2 * y_um - y_min_um - y_max_um) / (y_max_um - y_min_um);
  return u * u + v * v <= 1;
}

int region_holding(const std::vector<CouplingRegion>& regions, double x_um, double y_um) {
  for (auto k = static_cast<int>(regions.size()) - 1; k >= 0; --k)
    if (regions[static_cast<std::size_t>(k)].contains(x_um, y_um)) return k;
  return -1;
}

std::vector<CouplingRegion> read_coupling_regions(const json& regions, const std::string& path,
                                                  const JunctionConductances& base) {
  if (!regions.is_array())
    throw ManifestError(path, "expected a list of regions, got " + describe_json(regions));
  std::vector<CouplingRegion> out;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    if (!regions[i].is_object())
      throw ManifestError(index_path(path, i), "expected a region object, got " + describe_json(regions[i]));
    out.push_back(read_region(regions[i], index_path(path, i), base));
  }
  return out;
}

}  // namespace fibrodem

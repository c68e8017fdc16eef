#include "mechanics/mechano_electric_spec.hpp"

namespace fibrodem {

MechanoElectricSpec read_mechano_electric_spec(JsonReader r) {
  MechanoElectricSpec m;
  m.G_SAC_nS = r.number("G_SAC_nS", m.G_SAC_nS, 0.0, 1e6);
  m.E_SAC_mV = r.number("E_SAC_mV", m.E_SAC_mV, -200.0, 200.0);
  m.lambda_max = r.number("lambda_max", m.lambda_max, 1.0 + 1e-6, 10.0);
  m.stretch = r.text("stretch", "sarcomere", {"sarcomere", "tissue"}) == "tissue" ? StretchSource::tissue : StretchSource::sarcomere;
  m.cell_types_listed = r.has("cell_types");
  const std::vector<std::string> names = r.text_list("cell_types", {});
  for (std::size_t i = 0; i < names.size(); ++i) {
    std::size_t t = 0;
    while (t < kCellTypeNames.size() && names[i] != kCellTypeNames[t]) ++t;
    if (t == kCellTypeNames.size())
      throw ManifestError(index_path(r.path_of("cell_types"), i),
                          "expected a cell type (myocyte or fibroblast), got " + describe_json(names[i]));
    m.on_for_type[t] = true;
  }
  r.finish();
  return m;
}

}  // namespace fibrodem

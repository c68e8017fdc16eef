#include "coupling/coupling_spec.hpp"

namespace fibrodem {

CouplingSpec read_coupling_spec(JsonReader r) {
  CouplingSpec c;
  c.present = true;
  c.law = r.text("law", c.law, {"gap_junction"});
  c.D_m_nS = r.number("D_m_nS", c.D_m_nS, 0.0, 1e9);
  c.D_m_side_nS = r.number("D_m_side_nS", c.D_m_nS, 0.0, 1e9);
  c.D_f_nS = r.number("D_f_nS", c.D_f_nS, 0.0, 1e9);
  c.scheme = r.text("scheme", c.scheme, {"explicit", "implicit"});
  c.dt_ms = r.number("dt_ms", 0.0, 0.0, 1e3);
  if (r.has("regions")) c.regions = read_coupling_regions(r.raw("regions"), r.path_of("regions"), c.conductances());
  if (r.has("field")) c.field = read_coupling_field(r.raw("field"), r.path_of("field"));
  r.finish();
  return c;
}

}  // namespace fibrodem

#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

TechniqueDecl baked_technique() {
  TechniqueDecl t;
  t.name = "baked";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "baked lighting shown in the ambient term: light-maps (plain, RNM, SH-L1; --lightmap), "
      "ambient-cube probes for listed instances, per-vertex SH-L1 PRT (forward); switched on "
      "when such data is given";
  t.params = {
      float_param("intensity", 1.0f, 0.0f, 1e6f, "multiplies the light-map")
          .slider(UiHint::kLogarithmic, 0.01, 16),
  };
  return t;
}

}  // namespace illum::realtime

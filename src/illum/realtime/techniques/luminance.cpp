#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

TechniqueDecl luminance_technique() {
  TechniqueDecl t;
  t.name = "luminance";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "auto-exposure: the log-average luminance L_avg of the HDR frame (16×16 tile sums, one "
      "reduction); tonemap then scales by exposure · key / L_avg (off: --fixed-exposure)";
  t.default_on = true;
  t.switch_alias = "auto_exposure";
  return t;
}

}  // namespace illum::realtime

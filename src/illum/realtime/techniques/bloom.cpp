#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

TechniqueDecl bloom_technique() {
  TechniqueDecl t;
  t.name = "bloom";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "bright pass above a threshold at half resolution, separable Gaussian (σ = 8/3 texels), "
      "added before tone mapping";
  t.params = {
      float_param("strength", 0.5f, 0.0f, 100.0f,
                  "how much of the blurred bright pass is added (alias bloom_strength: a value "
                  "> 0 also switches bloom on, 0 off)")
          .aka("bloom_strength", true)
          .slider(UiHint::kLinear, 0, 2),
      float_param("threshold", 1.0f, 0.0f, 1e6f, "radiance above which pixels glow")
          .aka("bloom_threshold")
          .slider(UiHint::kLinear, 0, 10),
  };
  return t;
}

}  // namespace illum::realtime

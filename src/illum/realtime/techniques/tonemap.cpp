#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

TechniqueDecl tonemap_technique() {
  TechniqueDecl t;
  t.name = "tonemap";
  t.kind = TechniqueKind::kAddOn;
  t.summary =
      "exposure (× key / L_avg with luminance on), bloom added, a tone mapper, sRGB into the "
      "8-bit output the frame is written and shown from";
  t.default_on = true;
  t.params = {
      enum_param("operator", "aces", {"clamp", "reinhard", "aces", "agx"},
                 "clamp, Reinhard (luminance), ACES (Narkowicz fit), AgX (Sobotka)")
          .aka("tone_mapper"),
      float_param("exposure", 1.0f, 0.0f, 1e6f, "exposure multiplier")
          .aka("exposure")
          .slider(UiHint::kLogarithmic, 0.01, 100),
      float_param("key", 0.18f, 1e-4f, 10.0f,
                  "key value of auto-exposure (Reinhard et al. 2002): exposure · key / L_avg")
          .aka("key")
          .slider(UiHint::kLinear, 0.01, 1),
  };
  return t;
}

}  // namespace illum::realtime

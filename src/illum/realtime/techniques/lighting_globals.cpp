// The lighting globals: values every frame pipeline's lighting reads from the frame
// uniforms (set 0, shaders/common.glsl).
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

TechniqueDecl lighting_globals() {
  TechniqueDecl t;
  t.name = "lighting";
  t.kind = TechniqueKind::kGlobal;
  t.summary =
      "S002 §4.1 per-pixel lighting shared by every frame pipeline: emission + ambient + the "
      "lights' BRDF × irradiance × shadow";
  t.params = {
      bool_param("half_lambert", false, "Half-Lambert (0.5·N·L + 0.5)² instead of max(N·L, 0)")
          .aka("half_lambert"),
      color_param("ambient", Color(0.0f), 0.0f, 1e6f,
                  "constant ambient radiance × albedo where no light-map or probe applies "
                  "(illum frame: the scene's settings.ambient)")
          .aka("ambient"),
      int_param("single_light", -1, -1, 1000000, "light only with this light (−1: all lights)")
          .aka("single_light")
          .slider(UiHint::kLightIndex),
  };
  return t;
}

}  // namespace illum::realtime

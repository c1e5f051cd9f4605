#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

namespace {

// The parameters map and vsm share (each declares its own copy; the aliases set both).
std::vector<ParamDecl> map_params() {
  return {
      int_param("resolution", 512, 16, 8192, "side of a cube face, spot map or cascade (texels)")
          .structural()
          .aka("shadow_resolution")
          .slider(UiHint::kPowerOfTwo, 64, 4096),
      int_param("update_period", 0, 0, 1000000,
                "0: re-render the cube and spot maps only when the lights change; N: every N "
                "frames (cascades follow the camera every frame)")
          .structural()
          .aka("shadow_update_period")
          .slider(UiHint::kLinear, 0, 30),
      int_param("views_per_frame", 0, 0, 1000,
                "k > 0: re-render k cube faces or spot maps a frame in turn (round-robin) "
                "instead of all at once; all of them still when the lights change")
          .structural()
          .slider(UiHint::kLinear, 0, 12),
  };
}

}  // namespace

TechniqueDecl no_shadows_technique() {
  TechniqueDecl t;
  t.name = "none";
  t.kind = TechniqueKind::kShadowMethod;
  t.summary = "no shadows";
  return t;
}

TechniqueDecl shadow_map_technique() {
  TechniqueDecl t;
  t.name = "map";
  t.kind = TechniqueKind::kShadowMethod;
  t.summary =
      "shadow maps of distance/far: a cube per point light and wide spot, a 2-D map per spot up "
      "to 60°, 4 cascades for the first directional light; PCF with rotated Poisson taps";
  t.params = map_params();
  t.params.push_back(
      int_param("pcf_taps", 16, 1, 64, "PCF taps (1: hard shadows)").aka("pcf_taps"));
  t.params.push_back(float_param("pcf_radius", 1.5f, 0.0f, 64.0f, "PCF radius in texels")
                         .aka("pcf_radius")
                         .slider(UiHint::kLinear, 0, 8));
  t.params.push_back(
      float_param("bias", 0.002f, 0.0f, 1.0f, "depth bias relative to the light's far distance")
          .aka("shadow_bias")
          .slider(UiHint::kLogarithmic, 0, 0.02));
  return t;
}

TechniqueDecl vsm_technique() {
  TechniqueDecl t;
  t.name = "vsm";
  t.kind = TechniqueKind::kShadowMethod;
  t.summary =
      "variance shadow maps (S001 §4.2): the maps of `map` with the second moment, Chebyshev's "
      "bound with the light-bleeding threshold τ";
  t.params = map_params();
  t.params.push_back(float_param("tau", 0.2f, 0.0f, 0.99f,
                                 "light-bleeding threshold: [τ, 1] is remapped to [0, 1]")
                         .aka("vsm_tau"));
  return t;
}

}  // namespace illum::realtime

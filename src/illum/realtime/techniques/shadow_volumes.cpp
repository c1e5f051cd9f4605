#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

TechniqueDecl shadow_volume_technique() {
  TechniqueDecl t;
  t.name = "volume";
  t.kind = TechniqueKind::kShadowMethod;
  t.summary =
      "stencil shadow volumes (S002 §4.3): per light a z-fail stencil count of its volumes, "
      "then the light added where the count is 0 (forward: the scene again; deferred: one "
      "full-screen pass)";
  t.params = {
      int_param("update_period", 0, 0, 1000000,
                "0: rebuild the volumes only when the lights change; N: every N frames")
          .structural()
          .aka("shadow_update_period")
          .slider(UiHint::kLinear, 0, 30),
      bool_param("back_faces", false, "build the volumes from back-facing casters (S002 §4.3)")
          .aka("volume_back_faces"),
      enum_param("silhouettes", "gpu", {"gpu", "cpu"},
                 "gpu: one compute dispatch per light, drawn indirectly; cpu: the CPU reference "
                 "builder, uploaded")
          .structural()
          .aka("silhouettes"),
  };
  return t;
}

}  // namespace illum::realtime

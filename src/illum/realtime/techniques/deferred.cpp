#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

TechniqueDecl deferred_technique() {
  TechniqueDecl t;
  t.name = "deferred";
  t.kind = TechniqueKind::kFramePipeline;
  t.summary =
      "compact G-buffer after a depth pre-pass (albedo + exponent, two octahedral normals, "
      "specular + type; position from depth), then the lights over it";
  t.params = {
      enum_param("lighting", "compute", {"compute", "volumes"},
                 "compute: one dispatch looping over the lights; volumes: per-light light "
                 "volumes with the stencil trick (S001 §4.1)")
          .structural()
          .aka("deferred_lighting"),
  };
  return t;
}

}  // namespace illum::realtime

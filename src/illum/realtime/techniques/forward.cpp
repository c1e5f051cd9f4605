#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

TechniqueDecl forward_technique() {
  TechniqueDecl t;
  t.name = "forward";
  t.kind = TechniqueKind::kFramePipeline;
  t.summary =
      "depth pre-pass, then one shading pass over all lights with depth EQUAL (with stencil "
      "shadow volumes: emission + ambient, then the scene again per light)";
  return t;
}

}  // namespace illum::realtime

// The scene-draw globals: how SceneDrawer draws the scene from a view (realtime/scene_draw.h).
#include "illum/realtime/techniques/techniques.h"

namespace illum::realtime {

TechniqueDecl scene_draw_globals() {
  TechniqueDecl t;
  t.name = "scene_draw";
  t.kind = TechniqueKind::kGlobal;
  t.summary =
      "drawing the scene from a view: clusters culled against the view's frustum, sorted front "
      "to back, and (where the device has VK_EXT_conditional_rendering) against the depth";
  t.params = {
      // Off by default: on the H200 it made Sibenik's visibility frame 2.007 -> 2.320 ms
      // (bench/results/raster.md#h200-occlusion-culling): its views hide almost no whole cluster,
      // and each predicated draw and the pyramid cost time.
      bool_param("occlusion_culling", false,
                 "two-phase GPU occlusion culling of clusters in the depth pre-pass, the "
                 "visibility raster and the shadow views (realtime/occlusion_culling.h); the "
                 "image does not change; pays where views hide whole clusters")
          .aka("occlusion_culling"),
      bool_param("occlusion_culling_shadows", true,
                 "occlusion culling in the shadow views too (spot maps, cube faces, cascades: "
                 "many more clusters, each a predicated draw)")
          .aka("occlusion_culling_shadows"),
  };
  return t;
}

}  // namespace illum::realtime

// The virtual point lights of the `vpl` add-on (techniques/vpl.cpp, docs/realtime-vpl.md):
// the buffer vpl_build.comp writes and vpl_gather.comp sums. Must match `VplLight` in vpl.cpp.
#ifndef ILLUM_VPL_COMMON_GLSL
#define ILLUM_VPL_COMMON_GLSL

struct Vpl {
  vec4 position;  // xyz world position; w: 1 for a light, 0 for an empty block
  vec4 normal;    // xyz unit normal of the surface it stands for
  vec4 flux;      // rgb the flux it reflects diffusely (W, or the scene's flux unit)
};

#endif

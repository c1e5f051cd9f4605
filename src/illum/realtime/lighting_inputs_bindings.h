// The bindings of the lighting-inputs set (set 4: lighting_inputs.h), written so that
// C++ and GLSL both include this file and cannot drift apart. Binding 0 is the core's state
// block (which inputs are active); each registered input owns the range from its base on
// (its descriptor types: lighting_inputs.cpp). A new input takes the next free base.
#ifndef ILLUM_LIGHTING_INPUTS_BINDINGS_H
#define ILLUM_LIGHTING_INPUTS_BINDINGS_H

#ifdef __cplusplus
#define ILLUM_INPUTS_CONST inline constexpr
namespace illum::realtime {
#else
#define ILLUM_INPUTS_CONST const
#endif

ILLUM_INPUTS_CONST int kInputsSet = 4;  // descriptor set slot of the shading layout
ILLUM_INPUTS_CONST int kInputsStateBinding = 0;
// Per input: its base binding and its flag's index in the state block (registration order).
ILLUM_INPUTS_CONST int kProbesInputBase = 1;        // UBO, ambient cubes, draw cubes, volume
ILLUM_INPUTS_CONST int kPrtInputBase = 5;           // UBO, transfer points, VQ indices
ILLUM_INPUTS_CONST int kLightmapInputBase = 8;      // UBO, light-map array
ILLUM_INPUTS_CONST int kSsaoInputBase = 10;         // the "ssao" image
ILLUM_INPUTS_CONST int kLightVolumeInputBase = 11;  // UBO, the volume's copies 0 and 1
ILLUM_INPUTS_CONST int kLpvInputBase = 14;          // UBO, "lpv.accum"
ILLUM_INPUTS_CONST int kVplInputBase = 16;          // "vpl.irradiance"
ILLUM_INPUTS_CONST int kInputBindings = 17;         // one past the last binding
ILLUM_INPUTS_CONST int kProbesInput = 0;
ILLUM_INPUTS_CONST int kPrtInput = 1;
ILLUM_INPUTS_CONST int kLightmapInput = 2;
ILLUM_INPUTS_CONST int kSsaoInput = 3;
ILLUM_INPUTS_CONST int kLightVolumeInput = 4;
ILLUM_INPUTS_CONST int kLpvInput = 5;
ILLUM_INPUTS_CONST int kVplInput = 6;
ILLUM_INPUTS_CONST int kMaxLightingInputs = 8;  // flags in the state block

#ifdef __cplusplus
}  // namespace illum::realtime
#endif
#undef ILLUM_INPUTS_CONST

#endif

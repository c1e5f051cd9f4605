// The constants of the one auto-exposure rule (core/auto_exposure.h), written so that C++ and
// GLSL both include this file: shaders/luminance.comp builds the same histogram, so the
// offline and real-time images get the same exposure. Why these values: docs/realtime.md
// ("Exposure").
#ifndef ILLUM_CORE_AUTO_EXPOSURE_CONSTANTS_H
#define ILLUM_CORE_AUTO_EXPOSURE_CONSTANTS_H

#ifdef __cplusplus
#define ILLUM_EXPOSURE_CONST inline constexpr
namespace illum::exposure {
#else
#define ILLUM_EXPOSURE_CONST const
#endif

// log2-luminance histogram over [kMinLog2, kMaxLog2): 32 stops in bins of 1/8 stop. Below
// the range (black included) a pixel is not counted; above it, it counts in the top bin.
ILLUM_EXPOSURE_CONST int kHistogramBins = 256;
ILLUM_EXPOSURE_CONST float kMinLog2 = -16.0f;
ILLUM_EXPOSURE_CONST float kMaxLog2 = 16.0f;
// The mean log2 luminance of the pixels between these fractions of the counted ones, in
// luminance order, is mapped to kTarget.
ILLUM_EXPOSURE_CONST float kLowPercentile = 0.5f;
ILLUM_EXPOSURE_CONST float kHighPercentile = 0.95f;
ILLUM_EXPOSURE_CONST float kTarget = 0.18f;
// Rec. 709 luminance weights.
ILLUM_EXPOSURE_CONST float kLumaR = 0.2126f;
ILLUM_EXPOSURE_CONST float kLumaG = 0.7152f;
ILLUM_EXPOSURE_CONST float kLumaB = 0.0722f;

#ifdef __cplusplus
}  // namespace illum::exposure
#endif
#undef ILLUM_EXPOSURE_CONST

#endif

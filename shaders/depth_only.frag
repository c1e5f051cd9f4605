#version 450
// The fragment stage of depth-only pipelines (the depth pre-pass, the PCF cascades): it does
// nothing, and is there because a pipeline without one inherits fragment state from the one
// drawn before it. On the H200 (driver 580.159.04) the cascades took 0.483 ms after the
// visibility raster, whose fragment shader reads gl_PrimitiveID, and 0.391 ms with this stage
// (0.395 after the G-buffer pass either way; bench/results/raster.md#design-choices; the run is in git at c416128).
void main() {}

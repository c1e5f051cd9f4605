// Perspective camera (pinhole). Generates primary rays; the image plane has row 0 at the top.
#pragma once

#include "illum/core/math.h"

namespace illum {

struct Camera {
  vec3 position{0.0f, 0.0f, 5.0f};
  vec3 look_at{0.0f};
  vec3 up{0.0f, 1.0f, 0.0f};
  float fov_y = radians(45.0f);  // vertical field of view, radians

  // A camera looking at the centre of `bounds` from its +z side, far enough back that the
  // whole box fits the vertical field of view (used when a scene has no camera).
  static Camera framing(const Bounds3& bounds);

  // World-space ray through film position (px, py) in pixels of a width×height image
  // (continuous coordinates: pixel (i, j) spans [i, i+1) × [j, j+1)).
  Ray generate_ray(float px, float py, int width, int height) const;
  mat4 view_matrix() const;  // world → camera (right-handed, looking down −z)
  // Vulkan-style clip space: y down, depth in [0, 1].
  mat4 projection_matrix(float aspect, float z_near, float z_far) const;
};

}  // namespace illum

#include "illum/scene/camera.h"

namespace illum {

Ray Camera::generate_ray(float px, float py, int width, int height) const {
  const vec3 forward = glm::normalize(look_at - position);
  const vec3 right = glm::normalize(glm::cross(forward, up));
  const vec3 true_up = glm::cross(right, forward);
  const float tan_half = std::tan(0.5f * fov_y);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const float sx = (2.0f * px / static_cast<float>(width) - 1.0f) * tan_half * aspect;
  const float sy = (1.0f - 2.0f * py / static_cast<float>(height)) * tan_half;
  Ray ray;
  ray.origin = position;
  ray.direction = glm::normalize(forward + sx * right + sy * true_up);
  return ray;
}

Camera Camera::framing(const Bounds3& bounds) {
  Camera camera;
  if (bounds.empty()) return camera;
  const float radius = std::max(0.5f * bounds.diagonal(), 1e-3f);
  camera.look_at = bounds.center();
  camera.position =
      camera.look_at + vec3(0.0f, 0.25f * radius, radius / std::sin(0.5f * camera.fov_y));
  return camera;
}

mat4 Camera::view_matrix() const {
  return glm::lookAtRH(position, look_at, up);
}

mat4 Camera::projection_matrix(float aspect, float z_near, float z_far) const {
  mat4 p = glm::perspectiveRH_ZO(fov_y, aspect, z_near, z_far);
  p[1][1] *= -1.0f;  // Vulkan's clip space has y pointing down
  return p;
}

}  // namespace illum

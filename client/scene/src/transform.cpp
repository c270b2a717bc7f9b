#include "soltex/scene/transform.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

namespace soltex {

glm::dmat4 Transform::matrix() const {
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), translate);
  m = glm::rotate(m, glm::radians(rotate_degrees.z), glm::dvec3(0, 0, 1));
  m = glm::rotate(m, glm::radians(rotate_degrees.y), glm::dvec3(0, 1, 0));
  m = glm::rotate(m, glm::radians(rotate_degrees.x), glm::dvec3(1, 0, 0));
  return glm::scale(m, scale);
}

glm::dmat3 Transform::normal_matrix() const {
  return glm::transpose(glm::inverse(glm::dmat3(matrix())));
}

}  // namespace soltex

// Warps from the unit square to directions, with their exact solid-angle densities.
#pragma once

#include <glm/glm.hpp>

namespace btf {

// Cosine-weighted hemisphere around +z (Malley's method on a concentric disk mapping).
glm::vec3 squareToCosineHemisphere(glm::vec2 u);
float cosineHemispherePdf(const glm::vec3& w);

glm::vec3 squareToUniformHemisphere(glm::vec2 u);
float uniformHemispherePdf(const glm::vec3& w);

glm::vec3 squareToUniformSphere(glm::vec2 u);
float uniformSpherePdf();

// Concentric map of Shirley and Chiu 1997, square [0,1)^2 to unit disk.
glm::vec2 squareToConcentricDisk(glm::vec2 u);

// Directions around +z with density proportional to cos^exponent of the angle to +z (a Phong lobe);
// pdf = (exponent + 1) / (2 pi) * cos^exponent, zero below the pole's hemisphere.
glm::vec3 squareToCosinePowerHemisphere(glm::vec2 u, float exponent);
float cosinePowerHemispherePdf(const glm::vec3& w, float exponent);

}  // namespace btf

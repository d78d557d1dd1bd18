#include "bpm/geometry.h"

#include <limits>

namespace bpm {

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * norm(cross(b - a, c - a)); }

}  // namespace bpm

// SPDX-License-Identifier: LGPL-2.1-or-later
// Analytic caustic faces for the built-in scenes and for tests: height fields
// z = h(x, y) below a flat face whose outward normal is +z. Light that enters
// the flat face travels toward -z and leaves through the height field.
#pragma once

#include "caustic/mesh.hpp"

#include <functional>

namespace caustic {

struct HeightField {
  std::function<double(double, double)> height;          ///< z of the caustic face
  std::function<glm::dvec2(double, double)> gradient;    ///< (dh/dx, dh/dy)
  double half_width_x = 1.0;                             ///< footprint [-hx, hx] x [-hy, hy]
  double half_width_y = 1.0;
};

/// Samples a height field on an nx x ny vertex grid (nx, ny >= 2) with exact
/// outward normals (pointing away from the flat face, toward -z) and
/// triangles wound so that their geometric normal points outward too.
Mesh grid_mesh(const HeightField& surface, int nx, int ny);

/// Spherical cap of radius of curvature `radius`, apex at z = 0 (the lowest
/// point), over a square footprint of half-width `half_width` < radius / sqrt(2).
/// Paraxial back focal length from the apex: radius / (n - 1).
HeightField plano_convex_lens(double radius, double half_width);

/// Cylinder of radius `radius` curved along x, apex line at z = 0.
HeightField cylindrical_lens(double radius, double half_width);

/// Thickness t0 + a_x cos(k_x x) + a_y cos(k_y y): thicker glass where the
/// cosines peak (the face lies lower there).
HeightField sine_window(double amplitude_x, double k_x, double amplitude_y, double k_y, double half_width);

/// A plane z = 0: the flat slab.
HeightField flat_face(double half_width);

/// A prism: the plane z = tan(apex) x, tilted by `apex` radians about y
/// (thickest at -x, its base), over [-hx, hx] x [-hy, hy]. Light straight
/// down leaves it deviated by asin(n sin(apex)) - apex towards -x.
HeightField wedge(double apex, double half_width_x, double half_width_y);

/// A closed glass body (object.shape "solid"): the volume between `lower`
/// and `upper` (lower(x, y) < upper(x, y) over the common footprint, which
/// is `upper`'s), sampled on n x n vertices per face, closed by four flat
/// side walls. Every face keeps its own vertices and exact normals, so the
/// creases at the rim stay sharp; triangles are wound outward. Throws
/// std::invalid_argument for n < 2 or a footprint where the body is empty.
Mesh closed_body(const HeightField& upper, const HeightField& lower, int n);

/// A biconvex lens: spherical faces of radii r1 (upper) and r2 (lower),
/// `centre_thickness` apart on the axis, over a square footprint of
/// half-width `half_width`; apex of the upper face at z = centre_thickness / 2.
/// Thick-lens optics: 1/f = (n-1) (1/r1 + 1/r2 - (n-1) d / (n r1 r2)), and the
/// back focal length from the lower apex is f (1 - (n-1) d / (n r1)).
Mesh biconvex_lens(double r1, double r2, double centre_thickness, double half_width, int n);

}  // namespace caustic

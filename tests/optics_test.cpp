// SPDX-License-Identifier: LGPL-2.1-or-later
// Optics primitives against hand-computed values (docs/physics.md ch. 2-4).
#include "caustic/optics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>

using namespace caustic::optics;

namespace {
constexpr double kPi = std::numbers::pi;

Vec3 at_angle(double theta) { return {std::sin(theta), 0.0, -std::cos(theta)}; }  // toward -z, tilted in x
}  // namespace

TEST(Reflect, MirrorsAboutTheNormal) {
  const Vec3 r = reflect(glm::normalize(Vec3(1, 0, -1)), Vec3(0, 0, 1));
  EXPECT_NEAR(r.x, std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(r.z, std::sqrt(0.5), 1e-15);
  const Vec3 back = reflect(Vec3(0, 0, -1), Vec3(0, 0, -1));  // either side of the surface
  EXPECT_NEAR(back.z, 1.0, 1e-15);
}

TEST(Refract, NormalIncidencePassesStraight) {
  const auto t = refract(Vec3(0, 0, -1), Vec3(0, 0, 1), 1.0 / 1.5);
  ASSERT_TRUE(t);
  EXPECT_NEAR(t->direction.z, -1.0, 1e-15);
  EXPECT_NEAR(t->cos_i, 1.0, 1e-15);
  EXPECT_NEAR(t->cos_t, 1.0, 1e-15);
}

TEST(Refract, ObeysSnellsLaw) {
  // 30 degrees from air into n = 1.5: sin(theta_t) = 0.5 / 1.5 = 1/3.
  const auto t = refract(at_angle(kPi / 6), Vec3(0, 0, 1), 1.0 / 1.5);
  ASSERT_TRUE(t);
  EXPECT_NEAR(t->direction.x, 1.0 / 3.0, 1e-14);
  EXPECT_NEAR(t->direction.z, -std::sqrt(8.0 / 9.0), 1e-14);
  EXPECT_NEAR(glm::length(t->direction), 1.0, 1e-14);
}

TEST(Refract, FaceAgainstOrientsEitherNormal) {
  const Vec3 i = at_angle(0.3);
  EXPECT_LT(glm::dot(face_against(Vec3(0, 0, 1), i), i), 0.0);
  EXPECT_LT(glm::dot(face_against(Vec3(0, 0, -1), i), i), 0.0);
}

TEST(Refract, TotalInternalReflectionBeyondCriticalAngle) {
  const double n = 1.5;
  const double critical = std::asin(1.0 / n);  // 41.81 degrees
  EXPECT_NEAR(critical_angle(n), 0.729727656226966, 1e-12);
  EXPECT_TRUE(refract(at_angle(critical - 1e-6), Vec3(0, 0, 1), n));
  EXPECT_FALSE(refract(at_angle(critical + 1e-6), Vec3(0, 0, 1), n));
  // Just below the critical angle the transmitted ray grazes the surface.
  const auto grazing = refract(at_angle(critical - 1e-9), Vec3(0, 0, 1), n);
  ASSERT_TRUE(grazing);
  EXPECT_NEAR(std::abs(grazing->direction.x), 1.0, 1e-4);
}

TEST(Fresnel, NormalIncidenceGlass) {
  // ((n - 1) / (n + 1))^2 = 0.04 for n = 1.5, from either side.
  EXPECT_NEAR(fresnel(1.0, 1.0, 1.0, 1.5).reflectance, 0.04, 1e-15);
  EXPECT_NEAR(fresnel(1.0, 1.0, 1.5, 1.0).reflectance, 0.04, 1e-15);
  EXPECT_NEAR(fresnel_transmittance(1.0, 1.0, 1.5) * fresnel_transmittance(1.0, 1.5, 1.0), 0.9216, 1e-12);
}

TEST(Fresnel, BrewsterAngleCancelsParallelReflection) {
  const double theta_b = brewster_angle(1.0, 1.5);
  EXPECT_NEAR(theta_b, std::atan(1.5), 1e-15);
  const auto t = refract(at_angle(theta_b), Vec3(0, 0, 1), 1.0 / 1.5);
  ASSERT_TRUE(t);
  const auto f = fresnel(t->cos_i, t->cos_t, 1.0, 1.5);
  EXPECT_NEAR(f.r_p, 0.0, 1e-15);
  // r_s = (cos_i - n cos_t) / (cos_i + n cos_t) with cos_i = 1/sqrt(1 + n^2), cos_t = n/sqrt(1 + n^2).
  const double cos_i = 1.0 / std::sqrt(1.0 + 2.25), cos_t = 1.5 / std::sqrt(1.0 + 2.25);
  EXPECT_NEAR(f.r_s, (cos_i - 1.5 * cos_t) / (cos_i + 1.5 * cos_t), 1e-14);
  // Beyond Brewster r_p changes sign.
  const auto past = refract(at_angle(theta_b + 0.1), Vec3(0, 0, 1), 1.0 / 1.5);
  EXPECT_GT(fresnel(past->cos_i, past->cos_t, 1.0, 1.5).r_p, 0.0);
}

TEST(Fresnel, TotalInternalReflectionTransmitsNothing) {
  EXPECT_EQ(fresnel_transmittance(std::cos(0.9), 1.5, 1.0), 0.0);  // 51.6 deg > 41.8 deg
  EXPECT_GT(fresnel_transmittance(std::cos(0.5), 1.5, 1.0), 0.0);
}

TEST(Fresnel, GrazingIncidenceReflectsEverything) {
  EXPECT_NEAR(fresnel_transmittance(0.0, 1.0, 1.5), 0.0, 1e-12);
}

TEST(PointLightEntry, SatisfiesSnellAtTheEntryPoint) {
  const Plane plane{{0, 0, 1}, 0.0};
  const Vec3 light(3, -2, 10), v(-4, 5, -2.5);
  const double n = 1.5;
  const auto p = point_light_entry(light, v, plane, n);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->z, 0.0, 1e-12);
  const Vec3 in = glm::normalize(*p - light), inside = glm::normalize(v - *p);
  const double sin_i = glm::length(glm::cross(in, plane.normal));
  const double sin_t = glm::length(glm::cross(inside, plane.normal));
  EXPECT_NEAR(sin_i, n * sin_t, 1e-12);
  // The entry point lies in the plane of incidence (light, v, normal).
  EXPECT_NEAR(glm::dot(*p - light, glm::cross(v - light, plane.normal)), 0.0, 1e-9);
  // And refract() of the incident ray points at v.
  const auto t = refract(in, plane.normal, 1.0 / n);
  EXPECT_NEAR(glm::dot(t->direction, inside), 1.0, 1e-12);
}

TEST(PointLightEntry, StraightBelowTheLight) {
  const auto p = point_light_entry({1, 2, 5}, {1, 2, -3}, {{0, 0, 1}, 0.0}, 1.5);
  ASSERT_TRUE(p);
  EXPECT_NEAR(glm::length(*p - Vec3(1, 2, 0)), 0.0, 1e-12);
}

TEST(PointLightEntry, RejectsLightOnOrBehindThePlane) {
  EXPECT_FALSE(point_light_entry({0, 0, 0}, {1, 0, -1}, {{0, 0, 1}, 0.0}, 1.5));
  EXPECT_FALSE(point_light_entry({0, 0, -1}, {1, 0, -1}, {{0, 0, 1}, 0.0}, 1.5));
}

TEST(SolidAngle, OctantOfTheSphere) {
  // The triangle with corners on the three axes subtends 1/8 of 4 pi at the origin.
  EXPECT_NEAR(solid_angle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), kPi / 2, 1e-12);
}

TEST(SolidAngle, SmallDistantTriangleIsProjectedAreaOverDistanceSquared) {
  const double d = 1000.0;
  const double omega = solid_angle({0, 0, d}, {0, 0, 0}, {1e-2, 0, 0}, {0, 1e-2, 0});
  EXPECT_NEAR(omega / (0.5e-4 / (d * d)), 1.0, 1e-6);
}

TEST(Fresnel, ObliqueReflectanceFollowsFresnelsSineAndTangentLaws) {
  // R_s = sin²(θi − θt) / sin²(θi + θt), R_p = tan²(θi − θt) / tan²(θi + θt)
  // (Hecht, Optics, eq. 4.42-4.43 in angle form): the same physics by other
  // algebra, so a cosine swapped or left unsquared shows. Both ways through
  // the surface, up to the critical angle from the glass side.
  for (const auto& [n1, n2] : {std::pair{1.0, 1.5}, std::pair{1.5, 1.0}, std::pair{1.0, 1.333}}) {
    for (double degrees = 5; degrees < 90; degrees += 5) {
      const double ti = degrees * kPi / 180, sin_t = n1 / n2 * std::sin(ti);
      if (sin_t >= 1) continue;
      const double tt = std::asin(sin_t);
      const double rs = std::pow(std::sin(ti - tt) / std::sin(ti + tt), 2);
      const double rp = std::pow(std::tan(ti - tt) / std::tan(ti + tt), 2);
      const FresnelTerms f = fresnel(std::cos(ti), std::cos(tt), n1, n2);
      EXPECT_NEAR(f.r_s * f.r_s, rs, 1e-12) << n1 << " to " << n2 << " at " << degrees;
      EXPECT_NEAR(f.r_p * f.r_p, rp, 1e-12) << n1 << " to " << n2 << " at " << degrees;
      EXPECT_NEAR(fresnel_transmittance(std::cos(ti), n1, n2), 1 - 0.5 * (rs + rp), 1e-12)
          << n1 << " to " << n2 << " at " << degrees;
    }
  }
  // Hecht's figures for glass at 45 degrees: R_s 0.092, R_p 0.0085.
  const double cos_t = std::sqrt(1 - 0.5 / 2.25);
  EXPECT_NEAR(std::pow(fresnel(std::sqrt(0.5), cos_t, 1.0, 1.5).r_s, 2), 0.0920, 5e-5);
  EXPECT_NEAR(std::pow(fresnel(std::sqrt(0.5), cos_t, 1.0, 1.5).r_p, 2), 0.0085, 5e-5);
}

TEST(Fresnel, EqualIndicesAreNoInterfaceEvenAtGrazingIncidence) {
  // Index-1 glass is a scene the tests use (the inverse-square oracle): a ray
  // that grazes its face must pass whole, not turn into 0 / 0.
  for (double cos_i : {1.0, 0.5, 1e-9, 0.0}) {
    EXPECT_EQ(fresnel_transmittance(cos_i, 1.0, 1.0), 1.0) << cos_i;
    EXPECT_EQ(fresnel_transmittance(cos_i, 1.5, 1.5), 1.0) << cos_i;
  }
  // Unequal indices at grazing incidence and at the critical angle reflect everything.
  EXPECT_EQ(fresnel(0.0, std::sqrt(1 - 1 / 2.25), 1.0, 1.5).reflectance, 1.0);
  EXPECT_EQ(fresnel(std::sqrt(1 - 1 / 2.25), 0.0, 1.5, 1.0).reflectance, 1.0);
}

TEST(SolidAngle, DegenerateAndCoplanarCasesAreTheirLimits) {
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  EXPECT_NEAR(solid_angle({0.5, 0.5, 0}, a, b, c), 2 * kPi, 1e-12);  // in its plane, inside it
  EXPECT_NEAR(solid_angle({0.5, 0.5, 1e-9}, a, b, c), 2 * kPi, 1e-6);  // the limit from above
  EXPECT_EQ(solid_angle({3, 3, 0}, a, b, c), 0.0);                    // in its plane, outside it
  EXPECT_EQ(solid_angle({1, 1, 5}, a, b, {1, 0, 0}), 0.0);             // no area
  EXPECT_NEAR(critical_angle(1.0), kPi / 2, 1e-15);
}

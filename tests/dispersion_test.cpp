// SPDX-License-Identifier: LGPL-2.1-or-later
// Refractive index against wavelength, held against catalogue and
// handbook values (not the laws' own output): SCHOTT's N-BK7 data sheet,
// Corning's and Heraeus' fused silica, water's index at the sodium D line.
#include "caustic/dispersion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <stdexcept>

using namespace caustic::optics;

namespace {

const Medium& material(const char* name) {
  const Medium* m = find_material(name);
  if (!m) throw std::runtime_error(std::string("no material ") + name);
  return *m;
}

}  // namespace

TEST(Dispersion, Bk7MatchesSchottsDataSheet) {
  const Sellmeier& bk7 = material("bk7").law;
  // N-BK7 data sheet: n_d 1.51680, n_F 1.52238, n_C 1.51432, n_e 1.51872, v_d 64.17.
  EXPECT_NEAR(index(bk7, kLineD), 1.51680, 1e-5);
  EXPECT_NEAR(index(bk7, kLineF), 1.52238, 1e-5);
  EXPECT_NEAR(index(bk7, kLineC), 1.51432, 1e-5);
  EXPECT_NEAR(index(bk7, 546.0740), 1.51872, 1e-5);
  EXPECT_NEAR(abbe_number(bk7), 64.17, 0.02);
}

TEST(Dispersion, FusedSilicaMatchesItsCatalogues) {
  const Sellmeier& silica = material("fused_silica").law;
  // Corning 7980 and Heraeus Suprasil: n_d 1.4585, n_e 1.4601, v_d 67.8.
  EXPECT_NEAR(index(silica, kLineD), 1.4585, 1e-4);
  EXPECT_NEAR(index(silica, 546.0740), 1.4601, 1e-4);
  EXPECT_NEAR(abbe_number(silica), 67.8, 0.1);
}

TEST(Dispersion, WaterMatchesTheHandbookAtTheSodiumLine) {
  // 1.33299 against air at 20 degrees C and 589.3 nm (CRC Handbook); air's
  // own index there is 1.000277, and Daimon & Masumura's law is absolute.
  EXPECT_NEAR(index(material("water").law, 589.29), 1.33299 * 1.000277, 1e-4);
}

TEST(Dispersion, PolymersMatchTheirTypicalIndices) {
  // Typical catalogue n_d: PMMA 1.4905, polycarbonate 1.5849.
  EXPECT_NEAR(index(material("pmma").law, kLineD), 1.4905, 1e-3);
  EXPECT_NEAR(index(material("polycarbonate").law, kLineD), 1.5849, 1e-3);
  // Polycarbonate disperses about twice as much as PMMA (v_d about 30 against 57).
  EXPECT_LT(abbe_number(material("polycarbonate").law), 0.6 * abbe_number(material("pmma").law));
}

TEST(Dispersion, PolymersMatchTheirSourcesMeasurements) {
  // Sultanova, Kasarova & Nikolov (2009), the indices they measured (to
  // ±0.001) and fitted the laws to, at the lines the engine's visible range
  // holds: a typical n_d alone lets a coefficient drift by 0.3 %.
  const double nm[] = {435.8, 486.1, 587.6, 632.8, 703.0};
  const double pmma[] = {1.502, 1.497, 1.491, 1.489, 1.486};
  const double polycarbonate[] = {1.612, 1.599, 1.585, 1.580, 1.575};
  for (std::size_t i = 0; i < std::size(nm); ++i) {
    EXPECT_NEAR(index(material("pmma").law, nm[i]), pmma[i], 1e-3) << nm[i] << " nm";
    EXPECT_NEAR(index(material("polycarbonate").law, nm[i]), polycarbonate[i], 1e-3) << nm[i] << " nm";
  }
}

// Every material is transparent in the visible: its index falls as the
// wavelength grows (normal dispersion) wherever it was measured.
TEST(Dispersion, EveryMaterialDispersesNormallyWhereItWasMeasured) {
  ASSERT_GE(materials().size(), 5u);
  for (const Medium& m : materials()) {
    EXPECT_FALSE(m.source.empty()) << m.name;
    double previous = 0.0;
    int checked = 0;
    for (double nm = 380.0; nm <= 780.0; nm += 5.0) {
      if (!valid(m, nm)) continue;
      ++checked;
      const double n = index(m.law, nm);
      EXPECT_GT(n, 1.3) << m.name << " at " << nm;
      EXPECT_LT(n, 1.7) << m.name << " at " << nm;
      if (previous > 0.0) {
        EXPECT_LT(n, previous) << m.name << " at " << nm;
      }
      previous = n;
    }
    // Every catalogue law was measured over most of the visible (81 steps).
    EXPECT_GE(checked, 60) << m.name;
  }
  EXPECT_EQ(find_material("unobtainium"), nullptr);
}

TEST(Dispersion, CauchysLawThroughTwoLinesApproximatesACrownGlass) {
  // Through BK7's F and C lines: n = a + b / λ² holds the d line to 1e-4.
  const Sellmeier& bk7 = material("bk7").law;
  const double f = kLineF / 1000.0, c = kLineC / 1000.0;
  Cauchy law;
  law.b = (index(bk7, kLineF) - index(bk7, kLineC)) / (1.0 / (f * f) - 1.0 / (c * c));
  law.a = index(bk7, kLineC) - law.b / (c * c);
  EXPECT_NEAR(index(law, kLineD), index(bk7, kLineD), 1e-4);
  EXPECT_NEAR(law.b, 0.0042, 0.0005);  // a crown glass's dispersion coefficient
}

TEST(Dispersion, WavelengthsThatHaveNoIndexAreRefused) {
  const Sellmeier& bk7 = material("bk7").law;
  for (double nm : {0.0, -500.0, std::nan(""), double(INFINITY)}) {
    EXPECT_THROW(index(bk7, nm), std::invalid_argument) << nm;
    EXPECT_THROW(index(Cauchy{}, nm), std::invalid_argument) << nm;
  }
  // On the pole of BK7's first term (λ² = 0.0060 µm²) and just beyond it,
  // where the law has no real index.
  EXPECT_THROW(index(bk7, 1000.0 * std::sqrt(bk7.c[0])), std::invalid_argument);
  EXPECT_THROW(index(Sellmeier{{1.0, 0, 0, 0}, {0.04, 0, 0, 0}}, 190.0), std::invalid_argument);
}

// SPDX-License-Identifier: LGPL-2.1-or-later
// Colour from spectra, held against the CIE's published derived figures
// rather than the code's own sums: the white points of illuminants E, A and
// D65 (CIE 015:2018), points of the spectrum locus, the integral of y-bar,
// the sRGB white (IEC 61966-2-1), the 5 nm table's published column sums
// and D65's tristimulus values. A mistyped table row moves one of them.
#include "caustic/colour.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace caustic::optics;

namespace {

void expect_xy(const Xyz& c, double x, double y, double tolerance) {
  const auto xy = chromaticity(c);
  EXPECT_NEAR(xy[0], x, tolerance);
  EXPECT_NEAR(xy[1], y, tolerance);
}

}  // namespace

TEST(Colour, TheIntegralOfYBarIsTheCiesFigure) {
  // ∫ y-bar dλ = 106.857 over 360..830 nm; 380..780 holds all but 0.001 %.
  double sum = 0;
  for (int nm = 380; nm < 780; ++nm) sum += cie1931(nm + 0.5).y;
  EXPECT_NEAR(sum, 106.857, 0.002);  // measured 106.8565: linear between the 5 nm rows
  EXPECT_EQ(cie1931(379).y, 0.0);
  EXPECT_EQ(cie1931(781).x, 0.0);
  EXPECT_DOUBLE_EQ(cie1931(555).y, 1.0);  // the peak of photopic vision
}

TEST(Colour, TheTablesColumnsAddUpToTheirPublishedSums) {
  // CIE 15:2004 Table T.4 prints the sums of its 5 nm columns, 380-780 nm:
  // 21.371524, 21.371327, 21.371540. The rows are where cie1931() is exact;
  // one figure mistyped by 1e-4 shows, where the white points need 1e-2.
  Xyz sum;
  for (int nm = 380; nm <= 780; nm += 5) {
    const Xyz c = cie1931(nm);
    sum.x += c.x, sum.y += c.y, sum.z += c.z;
  }
  EXPECT_NEAR(sum.x, 21.371524, 2e-5);
  EXPECT_NEAR(sum.y, 21.371327, 2e-5);
  EXPECT_NEAR(sum.z, 21.371540, 2e-5);
}

TEST(Colour, D65sRowsGiveItsPublishedTristimulusValues) {
  // CIE 015:2018 gives D65 with the 1931 observer as X 95.04, Y 100,
  // Z 108.88; the 5 nm rows from 380 to 780 nm give 95.043 and 108.880. A
  // row of the D65 table off by 1 % moves Z by 0.08.
  Xyz sum;
  for (int nm = 380; nm <= 780; nm += 5) {
    const double s = power({Illuminant::d65}, nm);
    const Xyz c = cie1931(nm);
    sum.x += s * c.x, sum.y += s * c.y, sum.z += s * c.z;
  }
  EXPECT_NEAR(100 * sum.x / sum.y, 95.04, 0.01);
  EXPECT_NEAR(100 * sum.z / sum.y, 108.88, 0.01);
}

TEST(Colour, TheSpectrumLocusPassesThroughItsTabulatedPoints) {
  // CIE 015:2018 chromaticities of monochromatic stimuli (2-degree observer).
  expect_xy(cie1931(450), 0.15664, 0.01770, 5e-5);
  expect_xy(cie1931(520), 0.07430, 0.83380, 5e-5);
  expect_xy(cie1931(700), 0.73469, 0.26531, 5e-5);
}

TEST(Colour, StandardIlluminantsHaveTheirPublishedWhitePoints) {
  expect_xy(tristimulus({Illuminant::equal}), 1.0 / 3, 1.0 / 3, 1e-4);
  expect_xy(tristimulus({Illuminant::d65}), 0.31272, 0.32903, 2e-4);
  // Illuminant A is a blackbody at 2856 K (with c2 = 1.4388e-2 m K).
  expect_xy(tristimulus({Illuminant::blackbody, 2856}), 0.44757, 0.40745, 2e-4);
  // The Planckian locus at 6500 K (Wyszecki & Stiles, Table 1(3.11)).
  expect_xy(tristimulus({Illuminant::blackbody, 6500}), 0.3135, 0.3237, 3e-4);
}

TEST(Colour, TheLedIsItsDocumentedSpectrum) {
  // "led" is a model, not a standard (docs/physics.md §10): a Gaussian at
  // 450 nm (FWHM 20 nm) plus 0.6 of one at 560 nm (FWHM 120 nm), integrated
  // here against the CIE table, and the cool white that gives.
  const auto gaussian = [](double nm, double centre, double fwhm) {
    return std::exp(-4 * std::log(2.0) * std::pow((nm - centre) / fwhm, 2));
  };
  Xyz sum;
  for (int nm = 380; nm < 780; ++nm) {
    const double power = gaussian(nm + 0.5, 450, 20) + 0.6 * gaussian(nm + 0.5, 560, 120);
    const Xyz c = cie1931(nm + 0.5);
    sum.x += power * c.x, sum.y += power * c.y, sum.z += power * c.z;
  }
  const auto xy = chromaticity(sum);
  expect_xy(tristimulus({Illuminant::led}), xy[0], xy[1], 1e-9);
  EXPECT_NEAR(xy[0], 0.320, 1e-3);
  EXPECT_NEAR(xy[1], 0.354, 1e-3);
}

TEST(Colour, EachBandsWeightIsItsShareOfTheWhite) {
  // Equal energy in 8 bands of 50 nm: a band's weight is its CIE integral
  // in linear sRGB (IEC 61966-2-1's matrix, written out here) over the
  // whole visible's, channel by channel.
  const auto rgb = [](const Xyz& c) {
    return Rgb{3.2406 * c.x - 1.5372 * c.y - 0.4986 * c.z, -0.9689 * c.x + 1.8758 * c.y + 0.0415 * c.z,
               0.0557 * c.x - 0.2040 * c.y + 1.0570 * c.z};
  };
  const auto band = [](int from, int to) {
    Xyz sum;
    for (int nm = from; nm < to; ++nm) {
      const Xyz c = cie1931(nm + 0.5);
      sum.x += c.x, sum.y += c.y, sum.z += c.z;
    }
    return sum;
  };
  const Rgb white = rgb(band(380, 780));
  const auto samples = wavelength_samples({Illuminant::equal}, 8);
  ASSERT_EQ(samples.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    const int from = 380 + 50 * i;
    const Rgb expected = rgb(band(from, from + 50));
    EXPECT_EQ(samples[i].from_nm, from);
    EXPECT_EQ(samples[i].nm, from + 25);
    EXPECT_NEAR(samples[i].weight.r, expected.r / white.r, 1e-9) << "band " << i;
    EXPECT_NEAR(samples[i].weight.g, expected.g / white.g, 1e-9) << "band " << i;
    EXPECT_NEAR(samples[i].weight.b, expected.b / white.b, 1e-9) << "band " << i;
  }
}

TEST(Colour, D65IsTheSrgbWhite) {
  const Xyz d65 = tristimulus({Illuminant::d65});
  const Rgb white = linear_srgb({d65.x / d65.y, 1.0, d65.z / d65.y});
  EXPECT_NEAR(white.r, 1.0, 2e-3);
  EXPECT_NEAR(white.g, 1.0, 2e-3);
  EXPECT_NEAR(white.b, 1.0, 2e-3);
  EXPECT_NEAR(luminance(white), 1.0, 1e-3);
}

TEST(Colour, TheSrgbPrimariesAndWhiteHaveTheStandardsChromaticities) {
  // IEC 61966-2-1: R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06), white D65.
  const double expected[4][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}, {0.3127, 0.3290}};
  const Rgb colours[4] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  for (int k = 0; k < 4; ++k) {
    const auto xy = chromaticity(xyz(colours[k]));
    EXPECT_NEAR(xy[0], expected[k][0], 1e-3) << k;
    EXPECT_NEAR(xy[1], expected[k][1], 1e-3) << k;
    // And back: the two matrices are each other's inverse.
    const Rgb back = linear_srgb(xyz(colours[k]));
    EXPECT_NEAR(back.r, colours[k].r, 1e-3) << k;
    EXPECT_NEAR(back.g, colours[k].g, 1e-3) << k;
    EXPECT_NEAR(back.b, colours[k].b, 1e-3) << k;
  }
}

TEST(Colour, WavelengthWeightsSumToWhiteForEveryLightAndCount) {
  for (const LightSpectrum light : {LightSpectrum{Illuminant::d65}, LightSpectrum{Illuminant::equal},
                                    LightSpectrum{Illuminant::blackbody, 2700}, LightSpectrum{Illuminant::led}}) {
    for (int k : {1, 2, 3, 8, 16, kMaxWavelengths}) {
      const auto samples = wavelength_samples(light, k);
      ASSERT_EQ(samples.size(), static_cast<std::size_t>(k));
      Rgb sum;
      for (const auto& s : samples) {
        sum.r += s.weight.r;
        sum.g += s.weight.g;
        sum.b += s.weight.b;
        EXPECT_GT(s.to_nm, s.from_nm);
        EXPECT_GE(s.nm, s.from_nm);
        EXPECT_LE(s.nm, s.to_nm);
      }
      EXPECT_NEAR(sum.r, 1.0, 1e-12);
      EXPECT_NEAR(sum.g, 1.0, 1e-12);
      EXPECT_NEAR(sum.b, 1.0, 1e-12);
      EXPECT_EQ(samples.front().from_nm, kVisibleMinNm);
      EXPECT_EQ(samples.back().to_nm, kVisibleMaxNm);
    }
  }
}

TEST(Colour, ThreeBandsAreBlueGreenRed) {
  const auto s = wavelength_samples({Illuminant::d65}, 3);
  // 380-513 nm is mostly blue, 513-646 nm mostly green (with red), 646-780 nm red.
  EXPECT_GT(s[0].weight.b, s[0].weight.g);
  EXPECT_GT(s[0].weight.b, s[0].weight.r);
  EXPECT_GT(s[1].weight.g, s[1].weight.b);
  EXPECT_GT(s[2].weight.r, s[2].weight.g);
  EXPECT_GT(s[2].weight.r, s[2].weight.b);
}

TEST(Colour, AWarmLightPutsMoreOfEachChannelInTheLongerBands) {
  // Balanced, both lights are white; what differs is how the bands share
  // each channel: a 2700 K lamp has more deep red and less violet than a
  // 10000 K sky, so its red comes more from the last bands, its blue less
  // from the first.
  const auto warm = wavelength_samples({Illuminant::blackbody, 2700}, 8);
  const auto cool = wavelength_samples({Illuminant::blackbody, 10000}, 8);
  EXPECT_GT(warm[6].weight.r + warm[7].weight.r, cool[6].weight.r + cool[7].weight.r);
  EXPECT_LT(warm[0].weight.b, cool[0].weight.b);
}

TEST(Colour, BadCountsAndTemperaturesAreRefused) {
  EXPECT_THROW(wavelength_samples({}, 0), std::invalid_argument);
  EXPECT_THROW(wavelength_samples({}, kMaxWavelengths + 1), std::invalid_argument);
  EXPECT_THROW(wavelength_samples({Illuminant::blackbody, 10}, 4), std::invalid_argument);
  EXPECT_THROW(wavelength_samples({Illuminant::blackbody, std::nan("")}, 4), std::invalid_argument);
}

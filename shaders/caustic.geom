// SPDX-License-Identifier: LGPL-2.1-or-later
// Spreads each caustic-face triangle's flux over the screen pixels it
// overlaps. The triangle carries the constant relative irradiance
// E = flux / projected area (energy mode) or the report's area ratio; each
// pixel receives E times the exact fraction of the pixel the triangle covers
// (computed in caustic.frag), so a pixel holds the mean irradiance over its
// area and every triangle deposits exactly its flux, however small it is.
// The geometry emitted is the triangle's pixel-aligned bounding box, in the
// atlas tile of the surface its corners landed on (caustic/receivers.hpp).
// Corners that landed on different surfaces (or some on none) cannot span a
// triangle: each that landed takes a third of the flux to its own pixel.
layout(triangles) in;
layout(triangle_strip, max_vertices = 12) out;

in VertexData {
  vec2 screen;
  vec2 plane;
  vec3 footprint;
  float transmittance;
  float valid;
  vec3 tint;
  float share;
  float surface;
} vin[];

flat out float gIrradiance;  // E; for a collapsed triangle: flux per pixel area
flat out vec2 gA;            // corners in window pixels
flat out vec2 gB;
flat out vec2 gC;
flat out float gPoint;       // 1: collapsed to a point, all flux to one pixel
// The mean of the corners' tints: the exact mean of the tint interpolated
// linearly over the triangle, which its uniform flux density crosses.
flat out vec3 gTint;

uniform bool uPointLight;
uniform vec3 uLightDir;
uniform vec3 uLightPos;
uniform float uReferenceDistance2;  // point light: r_ref^2, so E0 = I0 / r_ref^2
uniform vec2 uResolution;           // pixels of the whole target
// Per surface: half its rectangle (world units) and its atlas tile (pixels,
// origin at the bottom left as GL counts them).
const int kSurfaces = 8;
uniform vec2 uSurfaceHalf[kSurfaces];
uniform vec2 uTileOrigin[kSurfaces];
uniform vec2 uTileSize[kSurfaces];
uniform bool uReportIntensity;
// Whether this pass keeps the triangle counts: a spectral frame counts its
// last wavelength only, sparing the others' atomics.
uniform bool uCount;

layout(std430, binding = 0) buffer TriangleCounters {
  uint drawn;
  uint dropped;        // a vertex missed the screen or met TIR
  uint positive;       // orientation on the screen, to count fold-overs
  uint negative;
  uint collapsed;      // smaller than kCollapsed: treated as a point
} counters;

// Below this many square pixels a triangle's corners are too close for a
// stable area; its flux goes to the pixel under its centroid.
const float kCollapsed = 1e-4;
const float kMaxReportRatio = 1e12;

float signedArea(vec2 a, vec2 b, vec2 c) {
  vec2 e1 = b - a, e2 = c - a;
  return 0.5 * (e1.x * e2.y - e1.y * e2.x);
}

vec2 toPixels(vec2 local, int surface) {
  return uTileOrigin[surface] + (local / uSurfaceHalf[surface] * 0.5 + 0.5) * uTileSize[surface];
}

vec2 worldPerPixel(int surface) { return 2.0 * uSurfaceHalf[surface] / uTileSize[surface]; }

void emitPixel(vec2 p) {
  gl_Position = vec4(p / uResolution * 2.0 - 1.0, 0.0, 1.0);
  EmitVertex();
}

// All the triangle's flux (its share of it) as a point in one pixel.
void emitPoint(vec2 at, float flux, vec3 tint, int surface) {
  vec2 wpp = worldPerPixel(surface);
  gPoint = 1.0;
  gIrradiance = flux / (wpp.x * wpp.y);
  gTint = tint;
  gA = gB = gC = at;
  vec2 cell = floor(at);
  emitPixel(cell + 0.25);  // a quad inside one pixel covers its centre only
  emitPixel(cell + vec2(0.75, 0.25));
  emitPixel(cell + vec2(0.25, 0.75));
  emitPixel(cell + 0.75);
  EndPrimitive();
}

void main() {
  if (vin[0].valid * vin[1].valid * vin[2].valid < 0.5) {
    if (uCount) atomicAdd(counters.dropped, 1u);
    return;
  }
  float transmittance = (vin[0].transmittance + vin[1].transmittance + vin[2].transmittance) / 3.0;
  int surface = int(vin[0].surface);
  bool together = surface >= 0 && vin[1].surface == vin[0].surface && vin[2].surface == vin[0].surface;
  int at = max(surface, 0);
  vec2 a = toPixels(vin[0].screen, at), b = toPixels(vin[1].screen, at), c = toPixels(vin[2].screen, at);
  float signedPixels = signedArea(a, b, c);
  float areaPixels = abs(signedPixels);
  vec2 wpp = worldPerPixel(at);
  float screenArea = areaPixels * wpp.x * wpp.y;

  float flux;
  if (uReportIntensity) {
    float planeArea = abs(signedArea(vin[0].plane, vin[1].plane, vin[2].plane));
    // Capped relative to the triangle, as the CPU's set-up does: no absolute area stands for zero.
    float ratio = screenArea < kMaxReportRatio * planeArea ? screenArea / planeArea : kMaxReportRatio;
    flux = transmittance * ratio * screenArea;
  } else if (uPointLight) {
    flux = transmittance * uReferenceDistance2 *
           solidAngle(uLightPos, vin[0].footprint, vin[1].footprint, vin[2].footprint);
  } else {
    vec3 areaVector = 0.5 * cross(vin[1].footprint - vin[0].footprint, vin[2].footprint - vin[0].footprint);
    flux = transmittance * abs(dot(areaVector, uLightDir));
  }
  flux *= (vin[0].share + vin[1].share + vin[2].share) / 3.0;
  if (!together) {  // parted among the surfaces
    if (!(flux > 0.0) || isinf(flux)) return;
    for (int k = 0; k < 3; ++k) {
      int own = int(vin[k].surface);
      if (own < 0) continue;
      // A corner on its rectangle's far edge belongs to the tile's last pixel,
      // not the neighbouring tile's first.
      vec2 p = min(toPixels(vin[k].screen, own), uTileOrigin[own] + uTileSize[own] - 0.5);
      if (uCount) atomicAdd(counters.collapsed, 1u);
      emitPoint(p, flux / 3.0, vin[k].tint, own);
    }
    return;
  }
  vec2 lo = min(min(a, b), c), hi = max(max(a, b), c);
  bool offscreen = any(greaterThan(lo, uResolution)) || any(lessThan(hi, vec2(0.0)));
  bool huge = any(greaterThan(hi - lo, 64.0 * uResolution));  // precision, not physics
  if (!(flux > 0.0) || isinf(flux) || offscreen || huge) {
    if (uCount && !(flux == 0.0) && !offscreen) atomicAdd(counters.dropped, 1u);
    return;
  }
  if (uCount) {
    atomicAdd(counters.drawn, 1u);
    if (signedPixels >= 0.0) atomicAdd(counters.positive, 1u);
    else atomicAdd(counters.negative, 1u);
  }

  float pixelArea = wpp.x * wpp.y;
  gA = a;
  gB = b;
  gC = c;
  gTint = (vin[0].tint + vin[1].tint + vin[2].tint) / 3.0;
  if (areaPixels < kCollapsed) {
    if (uCount) atomicAdd(counters.collapsed, 1u);
    gPoint = 1.0;
    gIrradiance = flux / pixelArea;
    vec2 cell = floor((a + b + c) / 3.0);
    lo = cell + 0.25;  // a quad inside one pixel covers its centre only
    hi = cell + 0.75;
  } else {
    gPoint = 0.0;
    gIrradiance = flux / screenArea;
    lo = floor(lo);
    hi = floor(hi) + 1.0;
  }
  emitPixel(lo);
  emitPixel(vec2(hi.x, lo.y));
  emitPixel(vec2(lo.x, hi.y));
  emitPixel(hi);
  EndPrimitive();
}

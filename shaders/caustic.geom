// Draws each caustic-face triangle at its projected screen position with the
// constant relative irradiance E = flux / projected area (energy mode), or
// the report's area ratio. Sub-pixel triangles become one pixel-sized square
// carrying the same flux, so a focus stays finite and keeps its energy.
layout(triangles) in;
layout(triangle_strip, max_vertices = 4) out;

in VertexData {
  vec2 screen;
  vec2 plane;
  vec3 footprint;
  float transmittance;
  float valid;
} vin[];

flat out float gIrradiance;

uniform bool uPointLight;
uniform vec3 uLightDir;
uniform vec3 uLightPos;
uniform float uReferenceDistance2;  // point light: r_ref^2, so E0 = I0 / r_ref^2
uniform vec2 uHalfSize;             // half the screen rectangle, world units
uniform vec2 uPixelSize;            // world units
uniform bool uReportIntensity;

layout(std430, binding = 0) buffer TriangleCounters {
  uint drawn;
  uint dropped;        // a vertex missed the screen or met TIR
  uint positive;       // orientation on the screen, to count fold-overs
  uint negative;
  uint subpixel;
} counters;

float signedArea(vec2 a, vec2 b, vec2 c) {
  vec2 e1 = b - a, e2 = c - a;
  return 0.5 * (e1.x * e2.y - e1.y * e2.x);
}

void emitAt(vec2 p, float irradiance) {
  gIrradiance = irradiance;
  gl_Position = vec4(p / uHalfSize, 0.0, 1.0);
  EmitVertex();
}

void main() {
  if (vin[0].valid * vin[1].valid * vin[2].valid < 0.5) {
    atomicAdd(counters.dropped, 1u);
    return;
  }
  float transmittance = (vin[0].transmittance + vin[1].transmittance + vin[2].transmittance) / 3.0;
  float screenSigned = signedArea(vin[0].screen, vin[1].screen, vin[2].screen);
  float screenArea = abs(screenSigned);
  float pixelArea = uPixelSize.x * uPixelSize.y;

  float flux;
  if (uReportIntensity) {
    float planeArea = abs(signedArea(vin[0].plane, vin[1].plane, vin[2].plane));
    flux = transmittance * screenArea / max(planeArea, 1e-6 * pixelArea) * screenArea;
  } else if (uPointLight) {
    flux = transmittance * uReferenceDistance2 *
           solidAngle(uLightPos, vin[0].footprint, vin[1].footprint, vin[2].footprint);
  } else {
    vec3 areaVector = 0.5 * cross(vin[1].footprint - vin[0].footprint, vin[2].footprint - vin[0].footprint);
    flux = transmittance * abs(dot(areaVector, uLightDir));
  }
  vec2 far = max(max(abs(vin[0].screen), abs(vin[1].screen)), abs(vin[2].screen));
  if (!(flux > 0.0) || isinf(flux) || any(greaterThan(far, 1e4 * uHalfSize))) {
    if (!(flux == 0.0)) atomicAdd(counters.dropped, 1u);
    return;
  }
  atomicAdd(counters.drawn, 1u);
  if (screenSigned >= 0.0) atomicAdd(counters.positive, 1u);
  else atomicAdd(counters.negative, 1u);

  if (screenArea >= pixelArea) {
    float irradiance = flux / screenArea;
    emitAt(vin[0].screen, irradiance);
    emitAt(vin[1].screen, irradiance);
    emitAt(vin[2].screen, irradiance);
  } else {
    atomicAdd(counters.subpixel, 1u);
    vec2 centre = (vin[0].screen + vin[1].screen + vin[2].screen) / 3.0;
    vec2 h = 0.5 * uPixelSize;
    float irradiance = flux / pixelArea;
    emitAt(centre + vec2(-h.x, -h.y), irradiance);
    emitAt(centre + vec2(h.x, -h.y), irradiance);
    emitAt(centre + vec2(-h.x, h.y), irradiance);
    emitAt(centre + vec2(h.x, h.y), irradiance);
  }
  EndPrimitive();
}

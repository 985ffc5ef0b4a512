// Additive blending sums the relative irradiance of overlapping triangles.
flat in float gIrradiance;
layout(location = 0) out float outIrradiance;

void main() { outIrradiance = gIrradiance; }

// The undefined-value check's own failure case (tests/spirv_undef_check.py, ctest
// kernels_no_undefined_values): `x` is written on one path and compared on every path,
// the pattern the kernels must not hold. The check must report it.
#version 460
layout(local_size_x = 1) in;
layout(std430, binding = 0) buffer Io { float v[]; };

void main() {
  float x;
  if (v[0] > 0.0) x = v[1];
  if (x > v[2]) v[3] = 1.0;
}

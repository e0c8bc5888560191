#version 450
// Core test: flat colour from the push constants.
#include "core_test_common.glsl"
layout(location = 0) out vec4 out_color;
void main() {
#ifdef CORE_TEST_INVERT
    out_color = vec4(1.0 - pc.color.rgb, pc.color.a);
#else
    out_color = pc.color;
#endif
}

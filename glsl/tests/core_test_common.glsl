// Shared declarations of the core test shaders (tests/gpu_core.rs).
layout(push_constant) uniform CoreTestPush {
    vec4 color;
    float level;
    float first_patch; // gl_PrimitiveID restarts per draw
} pc;

// Shared declarations of the core test shaders (tests/gpu_core.rs).
layout(push_constant) uniform CoreTestPush {
    vec4 color;
    float level;
} pc;

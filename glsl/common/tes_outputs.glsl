// The outputs every evaluation shader hands to shade.frag (world position, normal, colour class)
// and the default spacing (stage files define SPACING).
#ifndef TESSERA_TES_OUTPUTS_GLSL
#define TESSERA_TES_OUTPUTS_GLSL

#ifndef SPACING
#define SPACING equal_spacing
#endif

layout(location = 0) out vec3 t_world;
layout(location = 1) out vec3 t_normal;
layout(location = 2) flat out uint t_class;

#endif

// End caps of the adaptive scheme (Köbler 2013 §3.5; Gregory patches over the isolation level's
// points, Loop et al. 2009): control points precomputed per frame by endcap_points.comp, 36 per
// patch from GregoryPatchInfo.pad1 (20 points, 8 neighbour edge points, 8 neighbour face points);
// GregoryPatchInfo.pad0 is the patch's AdaptivePatch record.
#ifndef TESSERA_ENDCAP_GLSL
#define TESSERA_ENDCAP_GLSL

layout(std430, set = 0, binding = 13) readonly buffer EndCapPoints {
    vec4 endcap_points[];
};

#endif

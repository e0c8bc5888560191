// The outputs of every adaptive-scheme TES and the default spacing (common/tes_outputs.glsl).
#ifndef TESSERA_ADAPTIVE_TES_IO_GLSL
#define TESSERA_ADAPTIVE_TES_IO_GLSL

#include "tes_outputs.glsl"

#endif

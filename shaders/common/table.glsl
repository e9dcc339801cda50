// Buffer access through device addresses (GL_EXT_buffer_reference). One typed view per element type;
// kernels receive raw addresses in push constants and cast them to these views.
#ifndef WETDEM_TABLE_GLSL
#define WETDEM_TABLE_GLSL
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : enable
#extension GL_EXT_scalar_block_layout : require

layout(buffer_reference, std430, buffer_reference_align = 16) buffer Vec4s { vec4 v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) buffer Vec3s { vec3 v[]; };  // packed, 12 B
layout(buffer_reference, std430, buffer_reference_align = 16) buffer IVec4s { ivec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer UVec4s { uvec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Uints { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Ints { int v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Floats { float v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Int64s { int64_t v[]; };
#endif

// Buffer access through device addresses (GL_EXT_buffer_reference). One typed view per element type;
// kernels receive raw addresses in push constants and cast them to these views.
#ifndef WETDEM_TABLE_GLSL
#define WETDEM_TABLE_GLSL
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : enable
#extension GL_EXT_scalar_block_layout : require

layout(buffer_reference, std430, buffer_reference_align = 16) buffer Vec4s { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer IVec4s { ivec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer UVec4s { uvec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Uints { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Ints { int v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer Floats { float v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Int64s { int64_t v[]; };
// Whole 16- and 8-byte elements moved as 64-bit words. lavapipe (Mesa 22.3) loads and stores a device-address
// vector one component at a time, each component in its own loop over the SIMD lanes; 64-bit components halve
// the loops of the hot passes (docs/benchmark.md, "Loads and stores on lavapipe"). Bit-exact: the same bytes.
layout(buffer_reference, std430, buffer_reference_align = 16) buffer U64x2s { u64vec2 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer U64s { uint64_t v[]; };
uvec4 load_u4(uint64_t addr, uint i) {
  u64vec2 w = U64x2s(addr).v[i];
  return uvec4(unpack32(w.x), unpack32(w.y));
}
vec4 load_v4(uint64_t addr, uint i) { return uintBitsToFloat(load_u4(addr, i)); }
ivec4 load_i4(uint64_t addr, uint i) { return ivec4(load_u4(addr, i)); }
vec2 load_v2(uint64_t addr, uint i) { return uintBitsToFloat(unpack32(U64s(addr).v[i])); }
void store_u4(uint64_t addr, uint i, uvec4 x) { U64x2s(addr).v[i] = u64vec2(pack64(x.xy), pack64(x.zw)); }
void store_v4(uint64_t addr, uint i, vec4 x) { store_u4(addr, i, floatBitsToUint(x)); }
void store_i4(uint64_t addr, uint i, ivec4 x) { store_u4(addr, i, uvec4(x)); }
void store_v2(uint64_t addr, uint i, vec2 x) { U64s(addr).v[i] = pack64(floatBitsToUint(x)); }
#endif

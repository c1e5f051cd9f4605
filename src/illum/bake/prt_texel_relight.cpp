#include "illum/bake/prt_texel_relight.h"

#include <cpuid.h>
#include <immintrin.h>

#include <cstring>

#include <fmt/format.h>

#include "illum/core/error.h"
#include "illum/core/parallel.h"

namespace illum::bake {

namespace {

// The light laid out as the transfer is, [i][rgb], padded with zeros to a multiple of 12
// floats: the kernels walk a texel in blocks of 12 (three 4-lane registers), where the lanes'
// channels repeat as r g b r | g b r g | b r g b.
std::vector<float> light_weights(int bands, const ShLight& light) {
  if (light.bands != bands || light.coefficients.size() != size_t(bands) * size_t(bands))
    throw Error(
        fmt::format("relight: the light has {} bands, the transfer {}", light.bands, bands));
  const size_t n = 3 * light.coefficients.size();
  std::vector<float> w((n + 11) / 12 * 12, 0.0f);
  for (size_t i = 0; i < light.coefficients.size(); ++i)
    for (int c = 0; c < 3; ++c) w[3 * i + size_t(c)] = light.coefficients[i][c];
  return w;
}

void check_sizes(size_t values, int bands, size_t out_floats, const char* form) {
  const size_t per_texel = 3 * size_t(bands) * size_t(bands);
  if (values % per_texel != 0 || values / per_texel * 3 != out_floats)
    throw Error(fmt::format("relight ({}): {} transfer values and {} output floats for {} bands",
                            form, values, out_floats, bands));
}

// Σ over blocks of t × w, folded to r, g, b from the three registers' lanes.
inline void store_rgb(__m128 a, __m128 b, __m128 c, float* out) {
  alignas(16) float x[12];
  _mm_store_ps(x, a);
  _mm_store_ps(x + 4, b);
  _mm_store_ps(x + 8, c);
  out[0] = x[0] + x[3] + x[6] + x[9];
  out[1] = x[1] + x[4] + x[7] + x[10];
  out[2] = x[2] + x[5] + x[8] + x[11];
}

// One texel of `per_texel` floats (the last block read partly: its weights are zero, and
// `tail` copies the texel's remainder so no read passes its end).
template <typename Load>
__attribute__((always_inline)) inline void relight_one(const float* w, size_t per_texel, Load load,
                                                       float* out) {
  __m128 a = _mm_setzero_ps(), b = _mm_setzero_ps(), c = _mm_setzero_ps();
  const size_t full = per_texel / 12 * 12;
  for (size_t k = 0; k < full; k += 12) {
    a = _mm_add_ps(a, _mm_mul_ps(load(k), _mm_loadu_ps(w + k)));
    b = _mm_add_ps(b, _mm_mul_ps(load(k + 4), _mm_loadu_ps(w + k + 4)));
    c = _mm_add_ps(c, _mm_mul_ps(load(k + 8), _mm_loadu_ps(w + k + 8)));
  }
  store_rgb(a, b, c, out);
  for (size_t k = full; k < per_texel; ++k) out[k % 3] += load.scalar(k) * w[k];
}

struct LoadF32 {
  const float* t;
  __m128 operator()(size_t k) const { return _mm_loadu_ps(t + k); }
  float scalar(size_t k) const { return t[k]; }
};

float half_to_float_scalar(uint16_t h) {
  const uint32_t sign = uint32_t(h & 0x8000u) << 16;
  uint32_t exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu, bits;
  if (exponent == 0x1f) {
    bits = sign | 0x7f800000u | (mantissa << 13);
  } else if (exponent != 0) {
    bits = sign | ((exponent + 112) << 23) | (mantissa << 13);
  } else if (mantissa == 0) {
    bits = sign;
  } else {  // subnormal: normalise
    exponent = 113;
    while (!(mantissa & 0x400u)) {
      mantissa <<= 1;
      --exponent;
    }
    bits = sign | (exponent << 23) | ((mantissa & 0x3ffu) << 13);
  }
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

struct LoadHalfScalar {
  const uint16_t* t;
  __m128 operator()(size_t k) const {
    return _mm_setr_ps(half_to_float_scalar(t[k]), half_to_float_scalar(t[k + 1]),
                       half_to_float_scalar(t[k + 2]), half_to_float_scalar(t[k + 3]));
  }
  float scalar(size_t k) const { return half_to_float_scalar(t[k]); }
};

// The F16C conversion (4 halves a cycle) where the CPU has it; the build targets x86-64-v2,
// which does not include it, so it is chosen at run time.
struct LoadHalfF16c {
  const uint16_t* t;
  __attribute__((target("f16c"))) __m128 operator()(size_t k) const {
    return _mm_cvtph_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(t + k)));
  }
  float scalar(size_t k) const { return half_to_float_scalar(t[k]); }
};

// The loop itself carries the target, so the F16C loads inline into it (a lambda inside a
// target function would not inherit the target, and would call them once per 4 halves).
__attribute__((target("f16c"))) void relight_half_range_f16c(const uint16_t* t, int64_t begin,
                                                             int64_t end, size_t per_texel,
                                                             const float* w, float* out) {
  for (int64_t x = begin; x < end; ++x)
    relight_one(w, per_texel, LoadHalfF16c{t + size_t(x) * per_texel}, out + 3 * x);
}

// CPUID leaf 1, ECX bit 29 (cpuid.h's bit_F16C); read directly because clang's
// __builtin_cpu_supports does not know "f16c".
bool has_f16c() {
  unsigned a = 0, b = 0, c = 0, d = 0;
  return __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C) != 0;
}

}  // namespace

float half_to_float(uint16_t h) {
  return half_to_float_scalar(h);
}

std::vector<uint16_t> to_half(std::span<const float> values) {
  std::vector<uint16_t> out(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    uint32_t bits;
    std::memcpy(&bits, &values[i], sizeof bits);
    const uint32_t sign = (bits >> 16) & 0x8000u;
    const uint32_t abs = bits & 0x7fffffffu;
    uint32_t h;
    if (abs >= 0x7f800000u) {  // inf or NaN
      h = sign | 0x7c00u | (abs > 0x7f800000u ? 0x200u : 0u);
    } else if (abs >= 0x477ff000u) {  // rounds past the largest half (65504)
      h = sign | 0x7c00u;
    } else if (abs < 0x38800000u) {            // below the smallest normal half: subnormal or zero
      const int shift = 126 - int(abs >> 23);  // 14 + (113 − exponent) − 1 … as a right shift
      if (shift > 24) {
        h = sign;
      } else {
        const uint32_t mantissa = (abs & 0x7fffffu) | 0x800000u;
        const uint32_t kept = mantissa >> shift, rest = mantissa & ((1u << shift) - 1);
        const uint32_t half_way = 1u << (shift - 1);
        h = sign | (kept + (rest > half_way || (rest == half_way && (kept & 1u))));
      }
    } else {
      const uint32_t rebased = abs - (112u << 23);  // exponent 127 → 15
      const uint32_t kept = rebased >> 13, rest = rebased & 0x1fffu;
      h = sign | (kept + (rest > 0x1000u || (rest == 0x1000u && (kept & 1u))));
    }
    out[i] = uint16_t(h);
  }
  return out;
}

void relight_texels(std::span<const float> transfer, int bands, const ShLight& light,
                    std::span<float> out) {
  check_sizes(transfer.size(), bands, out.size(), "fp32");
  const std::vector<float> w = light_weights(bands, light);
  const size_t per_texel = 3 * size_t(bands) * size_t(bands);
  parallel_for(
      int64_t(out.size() / 3),
      [&](int64_t begin, int64_t end) {
        for (int64_t x = begin; x < end; ++x)
          relight_one(w.data(), per_texel, LoadF32{transfer.data() + size_t(x) * per_texel},
                      out.data() + 3 * x);
      },
      4096);
}

void relight_texels(std::span<const uint16_t> half_transfer, int bands, const ShLight& light,
                    std::span<float> out) {
  check_sizes(half_transfer.size(), bands, out.size(), "fp16");
  const std::vector<float> w = light_weights(bands, light);
  const size_t per_texel = 3 * size_t(bands) * size_t(bands), texels = out.size() / 3;
  if (has_f16c()) {
    parallel_for(
        int64_t(texels),
        [&](int64_t begin, int64_t end) {
          relight_half_range_f16c(half_transfer.data(), begin, end, per_texel, w.data(),
                                  out.data());
        },
        4096);
    return;
  }
  parallel_for(
      int64_t(texels),
      [&](int64_t begin, int64_t end) {
        for (int64_t x = begin; x < end; ++x)
          relight_one(w.data(), per_texel,
                      LoadHalfScalar{half_transfer.data() + size_t(x) * per_texel},
                      out.data() + 3 * x);
      },
      4096);
}

void relight_texels(const VqCodebook& codebook, int bands, const ShLight& light,
                    std::span<float> out) {
  const size_t per_texel = 3 * size_t(bands) * size_t(bands);
  if (size_t(codebook.dimension) != per_texel || codebook.indices.size() * 3 != out.size())
    throw Error(
        fmt::format("relight (VQ): codebook of dimension {} and {} indices, {} bands and "
                    "{} output floats",
                    codebook.dimension, codebook.indices.size(), bands, out.size()));
  const size_t count = size_t(codebook.count());
  std::vector<float> relit(3 * count);
  relight_texels(std::span<const float>(codebook.representatives), bands, light, relit);
  const uint16_t* index = codebook.indices.data();
  for (size_t i = 0; i < codebook.indices.size(); ++i)
    if (index[i] >= count)
      throw Error(fmt::format("relight (VQ): index {} of texel {} past the {} representatives",
                              index[i], i, count));
  parallel_for(
      int64_t(codebook.indices.size()),
      [&](int64_t begin, int64_t end) {
        for (int64_t x = begin; x < end; ++x)
          std::memcpy(out.data() + 3 * x, relit.data() + 3 * size_t(index[x]), 3 * sizeof(float));
      },
      16384);
}

}  // namespace illum::bake

// Per-pixel lighting of S002 §4.1 (ALGORITHMS.md item 22): ambient (light-map × N_z or a
// constant), emission, and per light Phong diffuse + specular with attenuation
// max(1 − (d/r)², 0) and culling beyond r; Half-Lambert (0.5·N·L + 0.5)² as an option.
// Radiometry follows the scene model so the image matches the offline renderers: a point
// light of intensity I gives irradiance I·cosθ/d² and the BRDF is the material's.
#ifndef ILLUM_LIGHTING_GLSL
#define ILLUM_LIGHTING_GLSL
#include "common.glsl"
#include "shadows.glsl"
#include "sh.glsl"

// Texture sampling hooks: fragment shaders sample with the implicit LOD of their quads; a
// compute pass (visibility_resolve.comp) defines these first to pass explicit gradients
// (SAMPLE_LIGHTMAP: inputs/lightmap.glsl).
#ifndef SAMPLE_MATERIAL
#define SAMPLE_MATERIAL(map, uv) texture(map, uv)
#endif

struct Surface {
  vec3 p;
  vec3 n;        // shading normal (normal-mapped), unit
  vec3 ng;       // geometric normal, unit, facing the viewer
  vec3 albedo;
  vec3 specular;
  float exponent;
  int type;      // MaterialType
  vec3 emission;
  float n_z;     // tangent-space z of the normal map (1 without one)
  vec3 n_ts;     // tangent-space shading normal ((0,0,1) without a normal map)
  vec2 uv1;
  vec3 prt_vertex;  // per-vertex PRT: the interpolated Σ T_i L_i (callers set it; prt.glsl)
};

// A shading normal that hides the viewer is bent towards ng until the mirror direction of v
// rises from the surface by min(0.9·(v·ng), 0.01), the least bend by bisection on the blend
// n → ng: the offline tracer's rule, operation for operation (trace/ray_tracer.cpp
// bent_for_valid_reflection), so a normal map seen at a grazing angle shades as the path
// tracer shades it instead of black.
vec3 bent_for_valid_reflection(vec3 n, vec3 ng, vec3 v) {
  float cos_g = dot(ng, v);
  if (!(cos_g > 0.0)) return n;
  float threshold = min(0.9 * cos_g, 0.01);
  if (dot(ng, 2.0 * dot(n, v) * n - v) >= threshold) return n;
  float lo = 0.0, hi = 1.0;
  for (int i = 0; i < 20; ++i) {
    float mid = 0.5 * (lo + hi);
    vec3 m = normalize(mix(n, ng, mid));
    if (dot(ng, 2.0 * dot(m, v) * m - v) >= threshold) hi = mid; else lo = mid;
  }
  return normalize(mix(n, ng, hi));
}

Surface load_surface(int material_index, vec3 p, vec3 normal, vec4 tangent, vec4 uv, bool front) {
  Material m = materials[material_index];
  Surface s;
  s.p = p;
  s.ng = normalize(front ? normal : -normal);
  s.albedo = m.albedo.rgb;
  if (m.textures.x >= 0) s.albedo *= SAMPLE_MATERIAL(albedo_map, uv.xy).rgb;
  s.specular = m.specular.rgb;
  if (m.textures.w >= 0) s.specular *= SAMPLE_MATERIAL(specular_map, uv.xy).rgb;
  s.exponent = m.specular.w;
  s.type = m.info.x;
  s.emission = m.emission.rgb;
  if (m.textures.z >= 0) s.emission *= SAMPLE_MATERIAL(emission_map, uv.xy).rgb;
  s.n = s.ng;
  s.n_z = 1.0;
  s.n_ts = vec3(0.0, 0.0, 1.0);
  if (m.textures.y >= 0 && dot(tangent.xyz, tangent.xyz) > 0.0) {
    vec3 t = normalize(tangent.xyz - s.ng * dot(s.ng, tangent.xyz));
    vec3 b = cross(s.ng, t) * tangent.w;
    vec3 tn = SAMPLE_MATERIAL(normal_map, uv.xy).xyz * 2.0 - 1.0;
    tn.xy *= m.emission.w;
    tn = normalize(tn);
    s.n_z = max(tn.z, 0.0);
    s.n_ts = tn;
    s.n = normalize(t * tn.x + b * tn.y + s.ng * tn.z);
    s.n = bent_for_valid_reflection(s.n, s.ng, normalize(views[push.view].camera_pos.xyz - p));
  }
  s.uv1 = uv.zw;
  s.prt_vertex = vec3(0.0);
  return s;
}

// The material's BRDF times π-free factors: f(l, v) for Lambert / Phong / Blinn.
vec3 brdf(Surface s, vec3 l, vec3 v) {
  vec3 f = s.albedo / kPi;
  if (s.type == 1) {  // Phong, energy-normalized
    vec3 r = reflect(-l, s.n);
    f += s.specular * (s.exponent + 2.0) / (2.0 * kPi) * pow(max(dot(r, v), 0.0), s.exponent);
  } else if (s.type == 2) {  // Blinn, with the offline BSDF's exact normal-incidence
    // normalization (n+2)(n+4) / (8π(2^(−n/2) + n)) (render/bsdf.cpp: the usual (n+8)/(8π)
    // reflects more than it receives; 3.9% brighter at n = 40)
    vec3 h = normalize(l + v);
    float n = s.exponent;
    f += s.specular * (n + 2.0) * (n + 4.0) / (8.0 * kPi * (exp2(-0.5 * n) + n)) *
         pow(max(dot(h, s.n), 0.0), n);
  }
  return f;
}

// Irradiance-times-BRDF of one light at the surface, before shadowing; returns false when
// the light is culled (outside its radius or spot cone, or behind the surface).
bool light_contribution(int i, Surface s, vec3 v, out vec3 radiance, out vec3 l) {
  Light light = lights[i];
  int type = int(light.color_type.w);
  float atten = 1.0;
  if (type == kLightDirectional) {
    l = -light.direction_cos.xyz;
  } else {
    vec3 to = light.position_range.xyz - s.p;
    float d2 = dot(to, to);
    float r = light.position_range.w;
    if (r > 0.0 && d2 >= r * r) return false;  // radius culling
    l = to * inversesqrt(d2);
    atten = 1.0 / d2;
    if (r > 0.0) atten *= max(1.0 - d2 / (r * r), 0.0);
    const float cos_axis = dot(-l, light.direction_cos.xyz);
    if ((type == kLightSpot || type == kLightLambertian) && cos_axis < light.direction_cos.w)
      return false;
    if (type == kLightLambertian) atten *= cos_axis;
  }
  float ndl = dot(s.n, l);
  float cos_term = frame.counts.y != 0 ? pow(0.5 * ndl + 0.5, 2.0) : max(ndl, 0.0);
  if (cos_term <= 0.0 || dot(s.ng, l) <= 0.0 && frame.counts.y == 0) return false;
  radiance = brdf(s, l, v) * light.color_type.rgb * atten * cos_term;
  return true;
}

// The shadowed direct light of the frame's lights (all, or frame.counts.z alone) at surface s
// seen along v: forward.frag's loop, the deferred compute lighting's and the shading bound's
// (shading_bound.frag), so the three run the same per-pixel work. `frag`: the pixel's
// gl_FragCoord.xy (it rotates the PCF taps).
vec3 direct_light(Surface s, vec3 v, vec2 frag) {
  int first = frame.counts.z >= 0 ? frame.counts.z : 0;
  int last = frame.counts.z >= 0 ? frame.counts.z + 1 : frame.counts.x;
  vec3 sum = vec3(0.0);
  for (int i = first; i < last; ++i) {
    vec3 radiance, l;
    if (!light_contribution(i, s, v, radiance, l)) continue;
    sum += radiance * cube_shadow(i, s.p, s.ng, frag);
  }
  return sum;
}

#include "lighting_inputs.glsl"

// The ambient term: the lighting inputs' indirect term (or the neutral albedo · ambient
// constant where none gives one) times their occlusion, unless it holds its own visibility,
// plus their specular and extra radiance. `draw`: the draw's index (colour passes push it
// as push.draw), for the probes; `frag`: the pixel's gl_FragCoord.xy, for screen-space inputs.
vec3 ambient_indirect(Surface s, LightingTerms t) {
  return t.has_indirect ? t.indirect : s.albedo * frame.ambient.rgb;
}

vec3 ambient_term(Surface s, int draw, vec2 frag) {
  LightingTerms t = gather_lighting_inputs(s, draw, frag);
  return ambient_indirect(s, t) * indirect_occlusion(t) + t.specular + t.extra;
}

#endif

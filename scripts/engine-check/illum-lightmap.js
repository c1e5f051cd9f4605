// A GLTFLoader plugin that shows the light-map of an `illum export` .glb in three.js.
//
// illum writes the light-map as an RGBM PNG (linear bytes, value = rgb · a · range, range in
// the material's MSFT_lightmap extras) holding E/π on TEXCOORD_1
// (docs/lightmap-export.md). three.js's lightMap is irradiance E, which its Lambert term divides by
// π, so the plugin sets lightMapIntensity = π and decodes RGBM in the shader.
//
// The map's light is added as Lambertian diffuse, albedo × E/π, the model the bake and illum's
// renderer use: three.js's own path would first take the specular share (F0 = 0.04, its
// energy compensation) off the diffuse light, a few per cent darker than the bake means.
// Lights the file marks `illum_baked` (their light is in the map) are switched off.
//
// The decode happens per texel before the bilinear blend (four texelFetch, nearest texels):
// letting the hardware filter the encoded bytes would blend rgb and a separately, and
// rgb·a of blended values is not the blend of the decoded ones where neighbouring texels
// have different multipliers. illum decodes at load and filters decoded values; this matches.
//
//   import { IllumLightmapPlugin } from './illum-lightmap.js';
//   loader.register((parser) => new IllumLightmapPlugin(parser));
import { NearestFilter, NoColorSpace, ShaderChunk } from 'three';

// three.js's light-map lines (lights_fragment_maps) and what replaces them.
const THREE_LIGHTMAP = [
  'vec4 lightMapTexel = texture2D( lightMap, vLightMapUv );',
  'vec3 lightMapIrradiance = lightMapTexel.rgb * lightMapIntensity;',
  'irradiance += lightMapIrradiance;',
].join('\n\t\t');
const ILLUM_LIGHTMAP =
  'vec3 lightMapIrradiance = illumRgbmBilinear( vLightMapUv ) * lightMapIntensity;\n' +
  'reflectedLight.indirectDiffuse += lightMapIrradiance * BRDF_Lambert( material.diffuseContribution );';

const DECODE = /* glsl */ `
uniform float illumRgbmRange;
vec3 illumRgbmTexel( ivec2 p, ivec2 size ) {
  vec4 t = texelFetch( lightMap, clamp( p, ivec2( 0 ), size - 1 ), 0 );
  return t.rgb * ( t.a * illumRgbmRange );
}
// Bilinear over texel centres, clamped at the edges: a linear clamp-to-edge sampler.
vec3 illumRgbmBilinear( vec2 uv ) {
  ivec2 size = textureSize( lightMap, 0 );
  vec2 p = uv * vec2( size ) - 0.5;
  ivec2 i = ivec2( floor( p ) );
  vec2 f = p - floor( p );
  vec3 a = mix( illumRgbmTexel( i, size ), illumRgbmTexel( i + ivec2( 1, 0 ), size ), f.x );
  vec3 b = mix( illumRgbmTexel( i + ivec2( 0, 1 ), size ), illumRgbmTexel( i + ivec2( 1, 1 ), size ), f.x );
  return mix( a, b, f.y );
}
`;

// The extension's decoding parameters, or a reason this plugin does not show the map.
export function illumLightmapExtras(extension) {
  const extras = (extension && extension.extras) || {};
  if (extras.encoding !== 'RGBM') return { error: 'not an illum RGBM light-map' };
  if (!(typeof extras.range === 'number' && extras.range > 0 && Number.isFinite(extras.range)))
    return { error: 'extras.range is not a positive number' };
  if ((extras.tone ?? 'none') !== 'none')
    return { error: `tone-mapped (${extras.tone}): display values, not light` };
  return { range: extras.range };
}

// Makes `material` decode its lightMap as illum's RGBM with multiplier range `range`.
export function useIllumRgbm(material, range) {
  material.onBeforeCompile = (shader) => {
    if (!ShaderChunk.lights_fragment_maps.includes(THREE_LIGHTMAP))
      throw new Error('three.js changed lights_fragment_maps: update illum-lightmap.js');
    shader.uniforms.illumRgbmRange = { value: range };
    shader.fragmentShader = shader.fragmentShader
      .replace('#include <lightmap_pars_fragment>', '#include <lightmap_pars_fragment>\n#ifdef USE_LIGHTMAP\n' + DECODE + '#endif\n')
      .replace(
        '#include <lights_fragment_maps>',
        ShaderChunk.lights_fragment_maps.replace(THREE_LIGHTMAP, ILLUM_LIGHTMAP)
      );
  };
  material.customProgramCacheKey = () => `illum-rgbm-${range}`;
  material.needsUpdate = true;
}

export class IllumLightmapPlugin {
  constructor(parser) {
    this.parser = parser;
    this.name = 'MSFT_lightmap';
    this.ranges = new Map(); // glTF material index → RGBM range
  }

  extendMaterialParams(materialIndex, params) {
    const def = this.parser.json.materials[materialIndex];
    const extension = def.extensions && def.extensions[this.name];
    if (!extension) return Promise.resolve();
    const { range, error } = illumLightmapExtras(extension);
    if (error) {
      console.warn(`materials[${materialIndex}] MSFT_lightmap: ${error}; not shown`);
      return Promise.resolve();
    }
    this.ranges.set(materialIndex, range);
    // assignTexture puts texCoord 1 on the texture's channel (geometry attribute uv1).
    return this.parser.assignTexture(params, 'lightMap', extension.lightmapTexture).then((texture) => {
      texture.colorSpace = NoColorSpace; // the bytes are linear
      texture.minFilter = NearestFilter; // the shader filters decoded texels itself
      texture.magFilter = NearestFilter;
      texture.generateMipmaps = false;
      params.lightMapIntensity = Math.PI; // the map holds E/π; three.js wants E
    });
  }

  afterRoot(gltf) {
    gltf.scene.traverse((object) => {
      if (!object.isMesh) return;
      for (const material of Array.isArray(object.material) ? object.material : [object.material]) {
        const reference = this.parser.associations.get(material);
        if (reference && this.ranges.has(reference.materials) && material.lightMap) {
          if (!material.isMeshStandardMaterial)
            console.warn(`${material.type} '${material.name}': the light-map is shown on standard materials only`);
          else useIllumRgbm(material, this.ranges.get(reference.materials));
        }
      }
    });
    if (this.ranges.size > 0)
      gltf.scene.traverse((object) => {
        if (object.isLight && object.userData.illum_baked === true) object.visible = false;
      });
  }
}

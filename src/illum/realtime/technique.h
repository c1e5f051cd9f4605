// One interface for every real-time technique. A technique is declared once (TechniqueDecl:
// name, kind, parameters with type, default, range or values, help, and whether a change
// is per-frame or structural) and listed in technique_registry.cpp; the CLI (`-p`,
// `--enable`, `--list`), the viewer's panel and the JSON listing all read the declaration.
// At run time a technique (class Technique) declares its resources and passes to the frame
// graph, writes its descriptor sets once the resources exist, and updates its uniforms each
// frame.
//
// Kinds: the frame pipeline (exclusive: forward, deferred), the shadow method (exclusive:
// none, map, vsm, volume), add-ons (any number: baked-lighting display, luminance, bloom,
// tone mapping, ...), and the globals (always on: the lighting parameters every pipeline
// reads from the frame's set 0).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <vulkan/vulkan.h>

#include "illum/core/color.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/lighting_inputs.h"

namespace illum {
class Image;
}

namespace illum::realtime {

enum class TechniqueKind { kGlobal, kFramePipeline, kShadowMethod, kAddOn };
const char* kind_name(TechniqueKind kind);  // "globals", "frame pipeline", ...

enum class ParamType { kBool, kInt, kFloat, kColor, kEnum, kString };
const char* type_name(ParamType type);  // "bool", "int", "float", "color", "enum", "string"

// Per-frame: applied to the running renderer at the next frame (uniforms, push constants);
// a change also re-runs the technique's passes scheduled "on change". Structural: the owning
// technique is rebuilt (its pipelines, resources and passes), the others are kept.
enum class ParamChange { kPerFrame, kStructural };

// How the viewer's panel shows a number: a linear or logarithmic slider, a power of two
// (slider over the exponent), or a light index (−1 = all, up to the scene's light count).
enum class UiHint { kLinear, kLogarithmic, kPowerOfTwo, kLightIndex };

using ParamValue = std::variant<bool, int, float, Color, std::string>;
std::string value_text(const ParamValue& value);  // "true", "16", "0.5", "[0, 0, 0]", "aces"

struct ParamDecl {
  std::string key;
  ParamType type = ParamType::kFloat;
  ParamValue default_value;
  double min = 0.0, max = 0.0;       // int, float, and each colour component
  std::vector<std::string> choices;  // enum
  std::string help;
  ParamChange change = ParamChange::kPerFrame;
  // A short key `-p` accepts as well (the keys from before the technique interface, e.g.
  // pcf_taps); several declarations may share one (shadow_resolution sets map and vsm).
  std::string alias;
  // The alias also switches the technique: on for a value > 0, off for 0 (bloom_strength).
  bool alias_switches = false;
  // The full key switches the technique too: on for a non-empty string (debug.show=NAME).
  bool key_switches = false;
  UiHint ui = UiHint::kLinear;
  double ui_min = 0.0, ui_max = 0.0;  // the panel's slider range; 0, 0: the declared range

  ParamDecl structural() const;
  ParamDecl aka(const std::string& short_key, bool switches = false) const;
  ParamDecl slider(UiHint hint, double lo = 0.0, double hi = 0.0) const;
};

ParamDecl bool_param(const std::string& key, bool fallback, const std::string& help);
ParamDecl int_param(const std::string& key, int fallback, int lo, int hi, const std::string& help);
ParamDecl float_param(const std::string& key, float fallback, float lo, float hi,
                      const std::string& help);
ParamDecl color_param(const std::string& key, Color fallback, float lo, float hi,
                      const std::string& help);
ParamDecl enum_param(const std::string& key, const std::string& fallback,
                     std::vector<std::string> choices, const std::string& help);
// Free text, checked by its technique when the frame is assembled (a resource name).
ParamDecl string_param(const std::string& key, const std::string& fallback,
                       const std::string& help);

class Technique;
class TechniqueContext;
struct ShadingTime;

struct TechniqueDecl {
  std::string name;
  TechniqueKind kind = TechniqueKind::kAddOn;
  std::string summary;
  std::vector<ParamDecl> params;
  bool default_on = false;   // add-ons switched on unless --disable'd
  std::string switch_alias;  // a boolean `-p` key that switches the add-on (auto_exposure)
  // Add-ons this one needs (`requires` is a keyword): switching it on switches them on,
  // transitively, and switching one of them off while it is on is refused. Add-ons only —
  // the pipeline and shadow method are the user's choice, not a technique's; the registry
  // refuses unknown names and cycles (check_declarations).
  std::vector<std::string> dependencies;
  // Builds the technique for a renderer; null for the globals, which have no passes (the
  // renderer writes their values into the frame uniforms).
  std::function<std::unique_ptr<Technique>(TechniqueContext&)> create;

  const ParamDecl* param(const std::string& key) const;  // null if not declared
};

// A technique at run time. Built when it is switched on (or a structural parameter of it
// changes); kept otherwise. Per-frame parameters are read through param() while recording,
// so they apply at the next frame without a rebuild.
class Technique {
 public:
  Technique(TechniqueContext& context, const TechniqueDecl& decl) : ctx_(context), decl_(decl) {}
  virtual ~Technique() = default;
  Technique(const Technique&) = delete;
  Technique& operator=(const Technique&) = delete;

  const std::string& name() const { return decl_.name; }

  // Its resources (created ones with size, format, usage beyond the accesses) and its
  // passes with their accesses and schedules. Called whenever the frame is (re)assembled.
  virtual void declare(FrameGraph& graph) = 0;
  // After the frame's resources exist (again): writes the descriptor sets that point at them.
  virtual void bind() {}
  // Each frame before recording: uniforms from the camera, lights and parameter values.
  virtual void update() {}

  // The shadow method's set: bound at kShadowSet of the shading pipeline layout
  // (frame_globals.h), with the resources sampled through it (the shadow maps). Only the
  // active shadow method fills that slot.
  virtual int shading_slot() const { return -1; }
  virtual VkDescriptorSet shading_set() const { return VK_NULL_HANDLE; }
  virtual std::vector<std::string> shading_reads() const { return {}; }
  // What the technique adds to the lighting inputs (set 4, lighting_inputs.h): light or
  // occlusion every frame pipeline's ambient term gathers. Asked when the frame is
  // assembled; each contribution's writer runs after bind().
  virtual std::vector<LightingContribution> lighting_inputs() const { return {}; }

 protected:
  template <typename T>
  T param(const std::string& key) const;
  // Invalidates, at the next frame, the passes whose schedules name `changes` (a technique
  // that moved geometry raises kGeometryChanged; kParametersChanged reaches its own passes).
  void raise(Changes changes) const;

  TechniqueContext& ctx_;
  const TechniqueDecl& decl_;
};

// The frame pipeline (forward, deferred): draws the scene and lights it.
class FramePipeline : public Technique {
 public:
  using Technique::Technique;
  // For shadow methods that mask each light with the stencil (volumes): called per light
  // inside a light scope (SceneDrawer::begin_light_scope: HDR target loaded, depth
  // read-only, the light's stencil count made), adds light `light`, unshadowed, where the
  // stencil is 0.
  virtual void record_masked_light(PassContext& pass, int light) = 0;
  // What record_masked_light() reads besides the depth test and the HDR target.
  virtual std::vector<Access> masked_light_reads() const { return {}; }
  // After a frame: the shading bound of the pipeline's fragment lighting pass
  // (measure/shading_bound.h), timed `repeats` times, and with `image` its output. False where
  // the pipeline has no such pass (its lighting is compute, or the stencil masks each light).
  virtual bool measure_shading(int /*repeats*/, ShadingTime* /*out*/, Image* /*image*/) {
    return false;
  }
};

// The shadow method (none, map, vsm, volume).
class ShadowMethod : public Technique {
 public:
  using Technique::Technique;
  // True for stencil volumes: the pipeline's main pass then writes emission + ambient only
  // and each light is added through FramePipeline::record_masked_light().
  virtual bool masks_lights() const { return false; }
};

}  // namespace illum::realtime

#include "illum/realtime/viewer_panel.h"

#include <algorithm>
#include <cmath>

#include "illum/core/error.h"
#include "illum/realtime/technique_registry.h"

namespace illum::realtime {

namespace {

const char* const kLightTypes[] = {"point", "spot", "directional", "area", "environment"};

bool combo(const char* label, std::string* value, const std::vector<std::string>& items) {
  int index = static_cast<int>(std::find(items.begin(), items.end(), *value) - items.begin());
  std::vector<const char*> names;
  for (const std::string& i : items) names.push_back(i.c_str());
  if (!ImGui::Combo(label, &index, names.data(), static_cast<int>(names.size()))) return false;
  *value = items[static_cast<size_t>(index)];
  return true;
}

// One widget for parameter `p` of technique `name`, by its type and UI hint. The declared
// range bounds the slider; the value is set through RenderSettings, which checks it.
void param_widget(RenderSettings* s, const std::string& name, const ParamDecl& p, int lights) {
  const std::string key = name + "." + p.key;
  const std::string label = p.key + (p.change == ParamChange::kStructural ? " *" : "");
  const double lo = p.ui_min != p.ui_max ? std::max(p.ui_min, p.min) : p.min;
  const double hi = p.ui_min != p.ui_max ? std::min(p.ui_max, p.max) : p.max;
  ImGui::PushID(key.c_str());
  ParamValue next = s->value(key);
  bool changed = false;
  switch (p.type) {
    case ParamType::kBool: {
      bool v = std::get<bool>(next);
      changed = ImGui::Checkbox(label.c_str(), &v);
      next = v;
      break;
    }
    case ParamType::kInt: {
      int v = std::get<int>(next);
      if (p.ui == UiHint::kPowerOfTwo) {
        int e = static_cast<int>(std::lround(std::log2(std::max(v, 1))));
        changed = ImGui::SliderInt((label + " (2^n)").c_str(), &e,
                                   static_cast<int>(std::lround(std::log2(lo))),
                                   static_cast<int>(std::lround(std::log2(hi))));
        v = 1 << e;
      } else if (p.ui == UiHint::kLightIndex) {
        changed =
            ImGui::SliderInt(label.c_str(), &v, -1, std::max(lights - 1, -1), v < 0 ? "all" : "%d");
      } else {
        changed = ImGui::SliderInt(label.c_str(), &v, static_cast<int>(lo), static_cast<int>(hi));
      }
      next = v;
      break;
    }
    case ParamType::kFloat: {
      float v = std::get<float>(next);
      const ImGuiSliderFlags flags =
          p.ui == UiHint::kLogarithmic ? ImGuiSliderFlags_Logarithmic : ImGuiSliderFlags_None;
      changed = ImGui::SliderFloat(label.c_str(), &v, static_cast<float>(lo),
                                   static_cast<float>(hi), "%.4g", flags);
      next = v;
      break;
    }
    case ParamType::kColor: {
      Color v = std::get<Color>(next);
      changed = ImGui::ColorEdit3(label.c_str(), &v.r,
                                  ImGuiColorEditFlags_HDR | ImGuiColorEditFlags_Float);
      next = v;
      break;
    }
    case ParamType::kEnum: {
      std::string v = std::get<std::string>(next);
      changed = combo(label.c_str(), &v, p.choices);
      next = v;
      break;
    }
    case ParamType::kString: {
      // Taken on Enter: a half-typed resource name would rebuild the frame at every key.
      char text[256] = {};
      std::get<std::string>(next).copy(text, sizeof(text) - 1);
      changed =
          ImGui::InputText(label.c_str(), text, sizeof(text), ImGuiInputTextFlags_EnterReturnsTrue);
      next = std::string(text);
      break;
    }
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s: %s", key.c_str(), p.help.c_str());
  if (changed) {
    try {
      s->set(key, next);
    } catch (const Error&) {
      // Outside the declared range (a colour dragged below 0): the value is not taken.
    }
  }
  ImGui::PopID();
}

void technique_section(RenderSettings* s, const TechniqueDecl& t, int lights, std::string* error) {
  ImGui::PushID(t.name.c_str());
  if (t.kind == TechniqueKind::kAddOn) {
    bool on = s->active(t.name);
    if (ImGui::Checkbox(("##on " + t.name).c_str(), &on)) {
      try {
        on ? s->enable(t.name) : s->disable(t.name);
      } catch (const Error& e) {
        *error = e.what();  // another add-on needs it: the toggle is refused
      }
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("switch %s on or off", t.name.c_str());
    ImGui::SameLine();
  }
  const bool open = ImGui::CollapsingHeader(t.name.c_str(), ImGuiTreeNodeFlags_DefaultOpen);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", t.summary.c_str());
  if (open && s->active(t.name))
    for (const ParamDecl& p : t.params) param_widget(s, t.name, p, lights);
  ImGui::PopID();
}

}  // namespace

std::vector<Light> scaled_lights(const PanelState& p) {
  std::vector<Light> out = p.lights;
  for (Light& l : out) {
    l.intensity *= p.light_scale;
    l.irradiance *= p.light_scale;
  }
  return out;
}

void draw_panel(const gpu::Context& ctx, RenderSettings* s, PanelState* p, Camera* camera,
                const Camera& home, const std::vector<gpu::PassTime>& times, double frame_ms,
                float panel_width, float panel_height) {
  ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(panel_width, panel_height), ImGuiCond_FirstUseEver);
  ImGui::Begin("illum view");
  // Half the width for the widget, half for its label: narrow panels stay readable.
  ImGui::PushItemWidth(ImGui::GetWindowWidth() * 0.45f);
  ImGui::Text("%s", ctx.device_name().c_str());
  ImGui::Text("%dx%d  %.1f ms/frame", s->width, s->height, frame_ms);
  combo("pipeline", &s->pipeline, technique_names(TechniqueKind::kFramePipeline));
  combo("shadows", &s->shadows, technique_names(TechniqueKind::kShadowMethod));
  ImGui::TextDisabled("* rebuilds its technique");
  if (!p->error.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", p->error.c_str());

  if (ImGui::CollapsingHeader("GPU time (ms)", ImGuiTreeNodeFlags_DefaultOpen)) {
    double total = 0.0;
    if (ImGui::BeginTable("passes", 2, ImGuiTableFlags_SizingStretchProp)) {
      auto row = [](const std::string& name, double ms) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(name.c_str());
        ImGui::TableNextColumn();
        ImGui::Text("%.3f", ms);
      };
      for (const gpu::PassTime& t : times) {
        row(std::string(2 * static_cast<size_t>(t.depth), ' ') + t.name, t.ms);
        if (t.name.rfind("cpu:", 0) != 0 && t.depth == 0) total += t.ms;
      }
      row("sum (GPU)", total);
      ImGui::EndTable();
    }
    if (!ctx.timestamps()) ImGui::TextDisabled("(device has no timestamps)");
  }
  const int lights = static_cast<int>(p->lights.size());
  for (const TechniqueDecl& t : technique_registry())
    if (t.kind == TechniqueKind::kAddOn || s->active(t.name))
      technique_section(s, t, lights, &p->error);
  if (ImGui::CollapsingHeader("Lights", ImGuiTreeNodeFlags_DefaultOpen)) {
    p->lights_changed |= ImGui::SliderFloat("intensity x", &p->light_scale, 0.0f, 16.0f, "%.3f",
                                            ImGuiSliderFlags_Logarithmic);
    for (size_t i = 0; i < p->lights.size(); ++i) {
      Light& l = p->lights[i];
      ImGui::PushID(static_cast<int>(i));
      const int type = std::clamp(static_cast<int>(l.type), 0, 4);
      if (ImGui::TreeNode("light", "light %zu (%s)", i, kLightTypes[type])) {
        Color& c = l.type == LightType::kDirectional ? l.irradiance : l.intensity;
        p->lights_changed |= ImGui::ColorEdit3("intensity", &c.r,
                                               ImGuiColorEditFlags_HDR | ImGuiColorEditFlags_Float);
        if (l.type != LightType::kDirectional) {
          p->lights_changed |= ImGui::DragFloat3("position", &l.position.x, 0.01f);
          p->lights_changed |= ImGui::DragFloat("range (0 = none)", &l.range, 0.01f, 0.0f, 1e6f);
        }
        if (ImGui::Button("reset")) {
          l = p->base_lights[i];
          p->lights_changed = true;
        }
        ImGui::TreePop();
      }
      ImGui::PopID();
    }
  }
  if (ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::SliderFloat("speed", &p->speed, 0.01f, 10.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    float fov = glm::degrees(camera->fov_y);
    if (ImGui::SliderFloat("fov y", &fov, 10.0f, 120.0f, "%.1f deg"))
      camera->fov_y = glm::radians(fov);
    ImGui::Text("at %.2f %.2f %.2f", camera->position.x, camera->position.y, camera->position.z);
    if (ImGui::Button("reset camera (R)")) *camera = home;
    ImGui::SameLine();
    if (ImGui::Button("print camera (C)")) p->print_camera = true;
    ImGui::TextDisabled("WASD move, Q/E down/up, Shift fast,\nright-drag look, Esc quit");
  }
  ImGui::PopItemWidth();
  p->panel_pos = ImGui::GetWindowPos();
  p->panel_size = ImGui::GetWindowSize();
  ImGui::End();
}

}  // namespace illum::realtime

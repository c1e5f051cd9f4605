// Technique dependencies and optional reads, without a GPU: the registry's declarations
// checked (unknown names, cycles, a pipeline named as a dependency), RenderSettings switching
// on what an add-on needs and refusing to switch off what an add-on on needs, and the frame
// graph dropping optional reads of resources nothing declares.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "illum/core/error.h"
#include "illum/realtime/frame_graph.h"
#include "illum/realtime/render_settings.h"
#include "illum/realtime/technique_registry.h"

namespace illum::realtime {
namespace {

TechniqueDecl add_on(const std::string& name, std::vector<std::string> needs) {
  TechniqueDecl t;
  t.name = name;
  t.kind = TechniqueKind::kAddOn;
  t.dependencies = std::move(needs);
  return t;
}

// The error check_declarations throws for `list`, or "" when it accepts it.
std::string refusal(const TechniqueList& list) {
  try {
    check_declarations(list);
  } catch (const InternalError& e) {
    return e.what();
  }
  return "";
}

TEST(TechniqueDependencies, TheRegistryIsConsistent) {
  EXPECT_EQ(refusal(technique_registry()), "");
  // The debug view writes over tone mapping's output.
  const TechniqueDecl* debug = find_technique("debug");
  ASSERT_TRUE(debug);
  EXPECT_EQ(debug->dependencies, std::vector<std::string>{"tonemap"});
}

TEST(TechniqueDependencies, UnknownNamesCyclesAndNonAddOnsAreCaught) {
  EXPECT_EQ(refusal({add_on("a", {"b"}), add_on("b", {})}), "");
  EXPECT_NE(refusal({add_on("a", {"nosuch"})}).find("'a' needs 'nosuch', which is not declared"),
            std::string::npos);
  const std::string cycle = refusal({add_on("a", {"b"}), add_on("b", {"c"}), add_on("c", {"a"})});
  EXPECT_NE(cycle.find("cycle: a -> b -> c -> a"), std::string::npos) << cycle;
  EXPECT_NE(refusal({add_on("a", {"a"})}).find("cycle: a -> a"), std::string::npos);
  TechniqueDecl pipeline;
  pipeline.name = "p";
  pipeline.kind = TechniqueKind::kFramePipeline;
  EXPECT_NE(refusal({add_on("a", {"p"}), pipeline}).find("only add-ons need add-ons"),
            std::string::npos);
  EXPECT_NE(refusal({add_on("a", {}), add_on("a", {})}).find("declared twice"), std::string::npos);
}

TEST(TechniqueDependencies, ARegistrationIsCheckedAndEndsWithItsObject) {
  const size_t before = technique_registry().size();
  EXPECT_THROW({ TechniqueRegistration r(add_on("lonely", {"nosuch"})); }, InternalError);
  // A second technique of a built-in name.
  EXPECT_THROW({ TechniqueRegistration r(add_on("tonemap", {})); }, InternalError);
  EXPECT_EQ(technique_registry().size(), before);
  {
    TechniqueRegistration r(add_on("extra", {"bloom"}));
    EXPECT_EQ(technique_registry().size(), before + 1);
    EXPECT_TRUE(find_technique("extra"));
  }
  EXPECT_EQ(technique_registry().size(), before);
  EXPECT_FALSE(find_technique("extra"));
}

TEST(TechniqueDependencies, EnablingSwitchesOnWhatIsNeededTransitively) {
  TechniqueRegistration low(add_on("needs_bloom", {"bloom"}));
  TechniqueRegistration high(add_on("needs_needs", {"needs_bloom"}));
  RenderSettings s;
  ASSERT_FALSE(s.active("bloom"));
  s.enable("needs_needs");
  EXPECT_TRUE(s.active("needs_bloom"));
  EXPECT_TRUE(s.active("bloom"));
  EXPECT_NO_THROW(s.check());
  const auto order = s.active_techniques();
  EXPECT_NE(std::find(order.begin(), order.end(), "bloom"), order.end());
}

TEST(TechniqueDependencies, DisablingWhatAnAddOnNeedsIsOneLineNamingBoth) {
  TechniqueRegistration low(add_on("needs_bloom", {"bloom"}));
  RenderSettings s;
  s.enable("needs_bloom");
  std::string message;
  try {
    s.disable("bloom");
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_EQ(message,
            "--disable bloom: 'needs_bloom' needs 'bloom' (switch 'needs_bloom' off first)");
  EXPECT_TRUE(s.active("bloom"));  // refused: nothing changed
  s.disable("needs_bloom");
  EXPECT_NO_THROW(s.disable("bloom"));
  EXPECT_FALSE(s.active("bloom"));
  // Settings made by hand past enable(): check() names the add-on and what it lacks.
  s.add_ons.insert("needs_bloom");
  try {
    s.check();
    ADD_FAILURE() << "check() took an add-on without what it needs";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "add-on 'needs_bloom' needs 'bloom', which is off");
  }
}

TEST(TechniqueDependencies, DebugShowSwitchesItselfAndToneMappingOn) {
  RenderSettings s;
  s.disable("tonemap");
  s.set_param("debug.show", "depth");
  EXPECT_TRUE(s.active("debug"));
  EXPECT_TRUE(s.active("tonemap"));
  EXPECT_EQ(s.get<std::string>("debug.show"), "depth");
  EXPECT_THROW(s.set_param("debug.show", 3), Error);  // text, not a number
  s.set_param("debug.show", "");
  EXPECT_FALSE(s.active("debug"));
}

ResourceDesc image(const std::string& name) {
  ResourceDesc r;
  r.name = name;
  r.frame_divisor = 1;
  r.format = VK_FORMAT_R16G16B16A16_SFLOAT;
  return r;
}

PassDesc pass(const std::string& name, std::vector<Access> accesses) {
  PassDesc p;
  p.name = name;
  p.technique = "t";
  p.phase = Phase::kPost;
  p.accesses = std::move(accesses);
  return p;
}

TEST(OptionalReads, DroppedWhereNothingDeclaresTheResource) {
  for (const bool declared : {false, true}) {
    FrameGraph g;
    g.add_resource(image("out"));
    if (declared) {
      g.add_resource(image("extra"));
      g.add_pass(pass("make", {{"extra", kStorageWrite, kComputeShader}}));
    }
    bool seen = !declared;
    PassDesc use = pass("use", {Access{"extra", kSampled, kComputeShader}.if_produced(),
                                {"out", kStorageWrite, kComputeShader}});
    use.record = [&](PassContext& p) { seen = p.reads("extra"); };
    g.add_pass(std::move(use));
    g.compile();
    EXPECT_EQ(g.reads("use", "extra"), declared);
    EXPECT_TRUE(g.reads("use", "out"));
    g.execute(VK_NULL_HANDLE, 0, nullptr);
    EXPECT_EQ(seen, declared);
    // Declared, the read is a real one: the pass waits for the writer.
    const auto& b = g.barriers();
    EXPECT_EQ(std::any_of(b.begin(), b.end(),
                          [](const Barrier& x) {
                            return x.resource == "extra" &&
                                   x.new_layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
                          }),
              declared);
  }
  // Not optional, an undeclared read is still the developer's error.
  FrameGraph g;
  g.add_pass(pass("use", {{"extra", kSampled, kComputeShader}}));
  EXPECT_THROW(g.compile(), InternalError);
}

}  // namespace
}  // namespace illum::realtime

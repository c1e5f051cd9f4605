// Frame graph ordering and update schedules (no GPU needed: passes record nothing).
#include <gtest/gtest.h>

#include "illum/core/error.h"
#include "illum/realtime/frame_graph.h"

namespace illum::realtime {
namespace {

TEST(FrameGraph, OrdersWritersBeforeReaders) {
  FrameGraph g;
  g.import_resource("scene");
  g.add_pass({"tonemap", {"hdr"}, {"ldr"}, UpdateSchedule::kEveryFrame, 1, nullptr});
  g.add_pass({"forward", {"scene", "shadow"}, {"hdr"}, UpdateSchedule::kEveryFrame, 1, nullptr});
  g.add_pass({"shadow", {"scene"}, {"shadow"}, UpdateSchedule::kOnChange, 1, nullptr});
  g.compile();
  EXPECT_EQ(g.order(), (std::vector<std::string>{"shadow", "forward", "tonemap"}));
}

TEST(FrameGraph, MissingProducerIsRejected) {
  FrameGraph g;
  g.add_pass({"forward", {"gbuffer"}, {"hdr"}, UpdateSchedule::kEveryFrame, 1, nullptr});
  EXPECT_THROW(g.compile(), InternalError);
}

TEST(FrameGraph, SchedulesEveryFrameEveryNAndOnChange) {
  FrameGraph g;
  g.add_pass({"a", {}, {"x"}, UpdateSchedule::kEveryFrame, 1, nullptr});
  g.add_pass({"b", {}, {"y"}, UpdateSchedule::kEveryN, 3, nullptr});
  g.add_pass({"c", {}, {"z"}, UpdateSchedule::kOnChange, 1, nullptr});
  EXPECT_EQ(g.execute(VK_NULL_HANDLE, 0, nullptr), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(g.execute(VK_NULL_HANDLE, 1, nullptr), (std::vector<std::string>{"a"}));
  EXPECT_EQ(g.execute(VK_NULL_HANDLE, 2, nullptr), (std::vector<std::string>{"a"}));
  EXPECT_EQ(g.execute(VK_NULL_HANDLE, 3, nullptr), (std::vector<std::string>{"a", "b"}));
  g.invalidate("c");
  EXPECT_EQ(g.execute(VK_NULL_HANDLE, 4, nullptr), (std::vector<std::string>{"a", "c"}));
}

}  // namespace
}  // namespace illum::realtime

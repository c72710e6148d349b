// What a tool touched and held on a tick (sim/runtime/tool_touch.h), as the recording keeps it,
// and where a replay departs from it (sim/report/touch_departure.h): hand-made contacts against
// the sums worked out by hand.

#include "sim/runtime/tool_touch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sim/report/touch_departure.h"
#include "sim/runtime/tissue_world.h"

namespace lap::sim {
namespace {

ToolContact contact(int32_t organ, const Eigen::Vector3d& force_on_organ_W) {
  ToolContact c;
  c.organ = organ;
  c.force_on_organ_W = force_on_organ_W;
  return c;
}

TEST(ToolTouch, SumsEachOrgansPushAsAVectorInTheOrderTheContactsNameThem) {
  const std::vector<ToolContact> c{contact(3, {1.0, 0.0, 0.0}), contact(5, {0.0, 0.0, 2.0}),
                                   contact(3, {0.0, 1.0, 0.0})};
  const ToolTouch t = tool_touch(c.data(), 3, true, false);
  EXPECT_TRUE(t.catheter_held);
  EXPECT_FALSE(t.duct_held);
  EXPECT_EQ(t.organs, 2);
  EXPECT_EQ(t.contacts, 3);
  ASSERT_EQ(t.listed(), 2U);
  EXPECT_EQ(t.organ[0], 3);
  EXPECT_EQ(t.organ_contacts[0], 2);
  EXPECT_FLOAT_EQ(t.force_n[0], static_cast<float>(std::sqrt(2.0)));
  EXPECT_EQ(t.organ[1], 5);
  EXPECT_EQ(t.organ_contacts[1], 1);
  EXPECT_FLOAT_EQ(t.force_n[1], 2.0F);
  EXPECT_EQ(t.organ_contacts[2], 0);  // unlisted entries stay zero
  EXPECT_EQ(t.force_n[2], 0.0F);
}

TEST(ToolTouch, JawsSqueezingAnOrganFromEitherSidePushItNowhere) {
  const std::vector<ToolContact> c{contact(1, {0.8, 0.0, 0.0}), contact(1, {-0.8, 0.0, 0.0})};
  const ToolTouch t = tool_touch(c.data(), 2, false, true);
  EXPECT_TRUE(t.duct_held);
  EXPECT_EQ(t.organs, 1);
  EXPECT_EQ(t.organ_contacts[0], 2);
  EXPECT_EQ(t.force_n[0], 0.0F);
}

TEST(ToolTouch, OrgansPastTheListedOnesAreCountedNotListed) {
  std::vector<ToolContact> c;
  for (int32_t o = 0; o < 6; ++o) c.push_back(contact(10 + o, {0.0, 0.0, 1.0}));
  c.push_back(contact(15, {0.0, 0.0, 1.0}));     // the sixth organ again
  c.push_back(contact(-1, {0.0, 0.0, 9.0}));     // no organ: left out
  c.push_back(contact(70000, {0.0, 0.0, 9.0}));  // an index the record cannot hold: left out
  const ToolTouch t = tool_touch(c.data(), static_cast<int32_t>(c.size()), false, false);
  EXPECT_EQ(t.organs, 6);
  EXPECT_EQ(t.contacts, 7);
  EXPECT_EQ(t.listed(), ToolTouch::kListedOrgans);
  for (size_t k = 0; k < ToolTouch::kListedOrgans; ++k) {
    EXPECT_EQ(t.organ[k], static_cast<uint16_t>(10 + k));
    EXPECT_EQ(t.organ_contacts[k], 1);
    EXPECT_FLOAT_EQ(t.force_n[k], 1.0F);
  }
  // More contacts than a tool has are not read.
  std::vector<ToolContact> many(20, contact(2, {1.0, 0.0, 0.0}));
  EXPECT_EQ(tool_touch(many.data(), 20, false, false).contacts, ToolModelInput::kMaxContacts);
}

TEST(ToolTouch, ATouchIsDescribedWithItsOrgansNames) {
  const std::vector<ToolContact> c{contact(0, {0.0, 1.25, 0.0}), contact(0, {0.0, 0.0, 0.0})};
  const std::vector<std::string> names{"Gallbladder"};
  EXPECT_EQ(describe_touch(tool_touch(c.data(), 2, true, false), names),
            "held the catheter, touched Gallbladder (2 contacts, 1.25 N)");
  EXPECT_EQ(describe_touch(ToolTouch{}, names), "touched nothing");
  const std::vector<ToolContact> d{contact(4, {0.5, 0.0, 0.0})};
  EXPECT_EQ(describe_touch(tool_touch(d.data(), 1, false, true), names),
            "held the duct, touched organ 4 (1 contact, 0.5 N)");
}

TEST(TouchDeparture, NamesTheFirstTickAndToolWhoseTouchDiffers) {
  std::vector<std::array<ToolTouch, 2>> live(10);
  std::vector<TickLog> replayed(12);
  for (size_t t = 0; t < replayed.size(); ++t) replayed[t].tick = static_cast<int64_t>(t);
  EXPECT_FALSE(touch_departure(live, replayed, {}, 1000.0));  // the ticks both have agree
  const std::vector<ToolContact> c{contact(0, {0.0, 0.0, 1.0})};
  live[7][1] = tool_touch(c.data(), 1, false, false);
  replayed[8].touch[0].catheter_held = true;  // later: not the first
  const std::optional<std::string> note = touch_departure(live, replayed, {"Liver"}, 1000.0);
  ASSERT_TRUE(note);
  EXPECT_EQ(*note,
            "the replay departs from the session at tick 7 (0.007 s): live, the right tool "
            "touched Liver (1 contact, 1 N); replayed, it touched nothing. The replay's figures "
            "from there on are not the session's");
}

}  // namespace
}  // namespace lap::sim

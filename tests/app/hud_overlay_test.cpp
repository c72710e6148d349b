// The heads-up display never covers the middle of the picture (app/hud_overlay.h): with its
// longest texts, three notices, a result and a pause, at two window sizes, every text's box
// (measured by VTK's text renderer) and every gauge's quad lie outside the middle rectangle, and
// each text shows what the HudState says. VTK objects only: nothing is rendered.

#include "app/hud_overlay.h"

#include <gtest/gtest.h>
#include <vtkCoordinate.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkRenderWindow.h>

#include <string>

namespace lap::app {
namespace {

HudState busiest() {
  HudState s;
  s.step = "Step 2 of 5";
  s.instruction = "Bring the catheter's tip to the ductotomy in the cystic duct";
  s.progress = "Depth 10.0 of 10.0 mm";
  s.timer = "59:59 / 60:00";
  s.scope = "30\xC2\xB0 scope  zoom 1.5x  camera assistant";
  s.result = "FAILED: duct injured, catheter dropped, instrument out of view";
  s.failed = true;
  for (size_t i = 0; i < 2; ++i) {
    s.hands[i] = {i == 0 ? "Left clip-applier" : "Right dissector",
                  12.3,
                  5.0,
                  2.46,
                  "hepatoduodenal_fat",
                  4.9,
                  5.0,
                  true,
                  true};
  }
  s.notices = {{"The right instrument is out of view", 1.0, true},
               {"Duct crushed by the jaws (12.5 N)", 0.6, true},
               {"Catheter in the common bile duct", 0.2, true}};
  s.loops = "PAUSED: forces off - press Space to resume";
  s.loops_alarm = true;
  return s;
}

TEST(HudOverlay, NothingIsDrawnOverTheMiddleOfThePicture) {
  for (const auto& [w, h] : {std::pair{1280, 720}, std::pair{1024, 680}}) {
    vtkNew<vtkRenderWindow> window;
    window->SetSize(w, h);
    vtkNew<vtkRenderer> renderer;
    window->AddRenderer(renderer);
    HudOverlay hud;
    hud.attach(renderer);
    const HudState s = busiest();
    hud.draw(s, w, h);
    const HudLayout l = HudLayout::for_size(w, h);
    int shown = 0;
    for (vtkTextActor* a : hud.texts()) {
      const std::string text = a->GetInput() != nullptr ? a->GetInput() : "";
      if (text.empty()) continue;
      ++shown;
      // VTK gives the box about the actor's anchor (its justification applied): moved to where
      // the anchor is, it is in the picture's pixels.
      double box[4];  // x min, x max, y min, y max [pixels]
      a->GetBoundingBox(renderer, box);
      const int* anchor = a->GetPositionCoordinate()->GetComputedDisplayValue(renderer);
      box[0] += anchor[0];
      box[1] += anchor[0];
      box[2] += anchor[1];
      box[3] += anchor[1];
      EXPECT_GT(box[1] - box[0], 10.0) << text;
      const bool clear =
          box[1] <= l.free_x0 || box[0] >= l.free_x1 || box[3] <= l.free_y0 || box[2] >= l.free_y1;
      EXPECT_TRUE(clear) << w << "x" << h << ": '" << text << "' at x " << box[0] << "-" << box[1]
                         << ", y " << box[2] << "-" << box[3];
      EXPECT_GE(box[0], 0.0) << text;
      EXPECT_LE(box[1], w) << text;
      EXPECT_GE(box[2], 0.0) << text;
      EXPECT_LE(box[3], h) << text;
    }
    // step, instruction, progress, timer, scope, result, loops, 2 gauges, 2 squeezes, 3 notices
    EXPECT_EQ(shown, 14);
    vtkPoints* bars = hud.bars()->GetPoints();
    for (vtkIdType p = 0; p < bars->GetNumberOfPoints(); ++p) {
      double x[3];
      bars->GetPoint(p, x);
      EXPECT_TRUE(x[1] <= l.free_y0 || x[1] >= l.free_y1) << "bar point " << p;
    }
  }
}

TEST(HudOverlay, TheTextsAreTheStates) {
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  window->AddRenderer(renderer);
  HudOverlay hud;
  hud.attach(renderer);
  const HudState s = busiest();
  hud.draw(s, 1280, 720);
  std::vector<std::string> texts;
  for (vtkTextActor* a : hud.texts()) texts.emplace_back(a->GetInput());
  for (const std::string& want :
       {s.step, s.instruction, s.progress, s.timer, s.scope, s.result, s.loops,
        std::string("Left clip-applier  12.3 N on hepatoduodenal_fat  (injury 5.0 N)"),
        std::string("squeeze 4.9 N  (crush 5.0 N)"), s.notices[0].text}) {
    EXPECT_NE(std::find(texts.begin(), texts.end(), want), texts.end()) << want;
  }
  // A probe's hand: no squeeze text.
  HudState probe = busiest();
  probe.hands[0].jaws = false;
  hud.draw(probe, 1280, 720);
  texts.clear();
  for (vtkTextActor* a : hud.texts())
    texts.emplace_back(a->GetInput() != nullptr ? a->GetInput() : "");
  // The right hand's squeeze still shown, the left's (a probe) not.
  EXPECT_EQ(std::count(texts.begin(), texts.end(), std::string("squeeze 4.9 N  (crush 5.0 N)")), 1);
}

}  // namespace
}  // namespace lap::app

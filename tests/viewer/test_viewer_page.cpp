// The page as a browser shows it: headless Chromium (WebGL on SwiftShader, the CPU) loads a
// rollout from the in-process server and its screenshot must show the cloth and a mesh obstacle
// beside it drawn. Skipped, with the reason, where Chromium is not installed (setup.sh installs
// it: docs/design.md §11).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "tests/util/shell.hpp"
#include "tests/util/temp_dir.hpp"
#include "tests/viewer/png_image.hpp"
#include "tests/viewer/viewer_fixture.hpp"

namespace fnopt {
namespace {

// The first of Debian's and other distributions' names for Chromium on the PATH, "" if none.
std::string chromium_binary() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    const CommandResult found = run_shell(std::string("command -v ") + name);
    if (found.status == 0) return found.output.substr(0, found.output.find('\n'));
  }
  return "";
}

// A 0.3 m cube's OBJ, left of the cloth (which spans x 0 to 1 at y = 0), in quads.
const char* const kCubeObj =
    "v -0.45 -0.3 -0.8\nv -0.15 -0.3 -0.8\nv -0.15 0 -0.8\nv -0.45 0 -0.8\n"
    "v -0.45 -0.3 -0.5\nv -0.15 -0.3 -0.5\nv -0.15 0 -0.5\nv -0.45 0 -0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

TEST(ViewerPage, HeadlessChromiumDrawsTheClothAndAMeshObstacle) {
  const std::string chromium = chromium_binary();
  if (chromium.empty()) GTEST_SKIP() << "Chromium is not installed (apt-get install chromium): the page is not drawn";
  const testing::TempDir dir;
  const std::string rollout = (dir.path() / "rollout.h5").string();
  testing::write_test_rollout(rollout, 12, 16, 30, "xy_v2", "mesh file=" + dir.write("cube.obj", kCubeObj));
  testing::RunningViewer viewer({rollout, ""});

  // --virtual-time-budget lets the page fetch its data and draw before the screenshot; a proxy
  // in the environment must not see 127.0.0.1.
  const std::string screenshot = (dir.path() / "page.png").string();
  const CommandResult run =
      run_shell("timeout 240 " + chromium + " --headless --no-sandbox --no-proxy-server --disable-dev-shm-usage" +
                " --use-angle=swiftshader --enable-unsafe-swiftshader --window-size=1280,900" +
                " --virtual-time-budget=8000 --user-data-dir=" + (dir.path() / "profile").string() +
                " --screenshot=" + screenshot + " http://127.0.0.1:" + std::to_string(viewer.port()) + "/");
  ASSERT_EQ(run.status, 0) << run.output;
  const testing::RgbImage image = testing::read_png(screenshot);
  ASSERT_EQ(image.width, 1280) << run.output;
  ASSERT_EQ(image.height, 900);

  // The 3D view (white, grey grid lines) spans the width below the header; the cloth is drawn in
  // the colour map's saturated colours, which nothing else in that area is. The cube, translucent
  // over the white background, is a pale grey-blue (blue above red, no channel dark), which
  // neither the grid's neutral greys nor the cloth's shaded purples are.
  int coloured = 0, obstacle = 0, total = 0;
  for (int y = 80; y < 540; ++y)
    for (int x = 40; x < 1240; ++x, ++total) {
      const std::uint8_t* p = image.pixel(x, y);
      const int largest = std::max({p[0], p[1], p[2]}), spread = largest - std::min({p[0], p[1], p[2]});
      coloured += spread > 40;
      obstacle += spread <= 40 && p[2] >= p[0] + 8 && largest < 240 && largest - spread >= 100;
    }
  EXPECT_GT(coloured, total / 100) << "the cloth covers under 1 % of the view: the page drew no frame";
  EXPECT_GT(obstacle, total / 50) << "the mesh obstacle covers under 2 % of the view: it was not drawn";
}

}  // namespace
}  // namespace fnopt

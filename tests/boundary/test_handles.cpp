#include <fnopt/boundary/handles.hpp>

#include <gtest/gtest.h>

#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

using testing::throws_error;

// 5 rows x 7 columns: (R-1)/2 = 2, (C-1)/2 = 3, vertex (i, j) = 7i + j.
const Grid kGrid = Grid::make(5, 7, 1.0);

std::vector<int> preset(const std::string& name) { return handle_preset(kGrid, name).vertices; }

TEST(HandlePresets, VerticesOnA5x7Grid) {
  EXPECT_EQ(preset("corner"), (std::vector<int>{0, 6}));          // (0,0), (0,6)
  EXPECT_EQ(preset("diagonal"), (std::vector<int>{0, 34}));       // (0,0), (4,6)
  EXPECT_EQ(preset("mid-edge"), (std::vector<int>{14, 20}));      // (2,0), (2,6)
  EXPECT_EQ(preset("corner-center"), (std::vector<int>{0, 17}));  // (0,0), (2,3)
  EXPECT_EQ(preset("single-mid-edge"), (std::vector<int>{3}));    // (0,3)
  EXPECT_EQ(preset("single-center"), (std::vector<int>{17}));     // (2,3)
}

TEST(HandlePresets, EvenSidesRoundTheMiddleDown) {
  const Grid grid = Grid::make(4, 6, 1.0);  // (R-1)/2 = 1, (C-1)/2 = 2
  EXPECT_EQ(handle_preset(grid, "single-center").vertices, (std::vector<int>{8}));
  EXPECT_EQ(handle_preset(grid, "mid-edge").vertices, (std::vector<int>{6, 11}));
}

TEST(HandlePresets, NamesAreTheSixPresetsAndEachResolves) {
  const auto names = handle_preset_names();
  EXPECT_EQ(names.size(), 6u);
  for (const auto& name : names) {
    const HandleSet set = handle_preset(kGrid, name);
    EXPECT_EQ(set.name, name);
    EXPECT_FALSE(set.vertices.empty());
  }
}

TEST(HandlePresets, UnknownPresetNamesTheFieldAndTheValidNames) {
  const auto unknown = [] { handle_preset(kGrid, "corners"); };
  EXPECT_TRUE(throws_error(unknown, "handles: unknown preset 'corners'"));
  EXPECT_TRUE(throws_error(unknown, "single-center"));
}

TEST(HandleList, ParsesPairsInOrder) {
  const HandleSet set = handle_vertices_from_list(kGrid, "4,6;0,0; 2 , 3 ");
  EXPECT_EQ(set.name, "vertices");
  EXPECT_EQ(set.vertices, (std::vector<int>{34, 0, 17}));
  EXPECT_EQ(handle_vertices_from_list(kGrid, "1,2").vertices, (std::vector<int>{9}));
}

TEST(HandleList, SyntaxOnlyParseNeedsNoGrid) {
  EXPECT_EQ(parse_handle_list("100,200;0,1"), (std::vector<std::pair<int, int>>{{100, 200}, {0, 1}}));
}

TEST(HandleList, RejectsEachMalformedEntry) {
  for (const std::string list :
       {"", " ", "1", "1,2,3", "a,b", "1.5,2", "1,2x", "1,2;", ";1,2", "1,2;;3,4", "1;2", ",", "1,", "99999999999,0"}) {
    EXPECT_TRUE(throws_error([&] { handle_vertices_from_list(kGrid, list); }, "handle-vertices: "))
        << "list '" << list << "'";
  }
}

TEST(HandleList, RejectsNegativeOutOfRangeAndDuplicateVertices) {
  EXPECT_TRUE(throws_error([] { handle_vertices_from_list(kGrid, "-1,0"); },
                           "handle-vertices: entry '-1,0' has a negative index"));
  EXPECT_TRUE(throws_error([] { handle_vertices_from_list(kGrid, "5,0"); },
                           "handle-vertices: vertex (5,0) is outside the 5x7 grid"));
  EXPECT_TRUE(
      throws_error([] { handle_vertices_from_list(kGrid, "0,7"); }, "handle-vertices: vertex (0,7) is outside"));
  EXPECT_TRUE(throws_error([] { handle_vertices_from_list(kGrid, "1,1;0,0;1,1"); },
                           "handle-vertices: vertex (1,1) is listed twice"));
  EXPECT_NO_THROW(handle_vertices_from_list(kGrid, "4,6"));
}

}  // namespace
}  // namespace fnopt

// map.csv through its one table of columns (reduce/map_table.hpp): the cells characterize writes
// are the cells predict and design read back, every figure and count to the digits written; a
// figure predict needs that is missing is refused naming the file and the column.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "bagdem/error.hpp"
#include "bagdem/reduce/map_table.hpp"
#include "bagdem/reduce/predict.hpp"
#include "support.hpp"

using namespace bagdem;

TEST(MapTable, WrittenCellsReadBackTheSame) {
  bagdem::testing::TempDir t;
  std::vector<MapCell> cells;
  for (double g : {1.0, 3.0})
    for (double f : {20.0, 40.0}) {
      MapCell c;
      c.gamma = g, c.frequency = f, c.amplitude = g * 9.81 / std::pow(2 * M_PI * f, 2);
      c.starts = 3, c.steady = 2, c.e_starts = 1, c.e_method = g > 2 ? "impact" : "none";
      double k = 0;
      for (const MapFigure& fig : map_figures()) (c.*fig.field).mean = 0.1 * ++k * g + f, (c.*fig.field).ci95 = 0.01 * k;
      c.e.ci95 = std::nan("");  // one start: no interval
      cells.push_back(c);
    }
  write_map_csv(t.path / "map.csv", cells);
  const std::vector<MapCell> back = read_map_csv(t.path / "map.csv", {&MapCell::M_eff, &MapCell::C_eff});
  ASSERT_EQ(back.size(), cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) {
    EXPECT_DOUBLE_EQ(back[i].gamma, cells[i].gamma);
    EXPECT_DOUBLE_EQ(back[i].frequency, cells[i].frequency);
    EXPECT_NEAR(back[i].amplitude, cells[i].amplitude, 1e-9 * cells[i].amplitude);
    EXPECT_EQ(back[i].starts, 3u);
    EXPECT_EQ(back[i].steady, 2u);
    EXPECT_EQ(back[i].e_starts, 1u);
    EXPECT_EQ(back[i].e_method, cells[i].e_method);
    for (const MapFigure& fig : map_figures()) {
      EXPECT_NEAR((back[i].*fig.field).mean, (cells[i].*fig.field).mean, 1e-9 * std::abs((cells[i].*fig.field).mean)) << fig.name;
      if (std::isnan((cells[i].*fig.field).ci95)) EXPECT_TRUE(std::isnan((back[i].*fig.field).ci95)) << fig.ci95;
      else EXPECT_NEAR((back[i].*fig.field).ci95, (cells[i].*fig.field).ci95, 1e-12) << fig.ci95;
    }
  }
  // predict's view of the same file.
  const EffectiveMap m = read_effective_map(t.path / "map.csv");
  EXPECT_EQ(m.gamma, (std::vector<double>{1, 3}));
  EXPECT_EQ(m.frequency, (std::vector<double>{20, 40}));
  EXPECT_NEAR(m.M_eff[3], cells[3].M_eff.mean, 1e-9 * cells[3].M_eff.mean);
}

TEST(MapTable, AMissingFigurePredictNeedsIsRefusedNamingIt) {
  bagdem::testing::TempDir t;
  std::ofstream(t.path / "map.csv") << "gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg]\n1,20,0.1,0\n1,40,0.1,0\n3,20,0.1,0\n3,40,0.1,0\n";
  try {
    read_effective_map(t.path / "map.csv");
    FAIL() << "a map without C_eff was read";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find((t.path / "map.csv").string()), std::string::npos) << m;
    EXPECT_NE(m.find("C_eff"), std::string::npos) << m;
  }
  // Figures predict does not read may be absent: they read as NaN.
  std::ofstream(t.path / "map.csv", std::ios::trunc)
      << "gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg],C_eff [N s/m],C_eff_ci95 [N s/m]\n1,20,0.1,0,2,0\n";
  const std::vector<MapCell> c = read_map_csv(t.path / "map.csv", {&MapCell::M_eff, &MapCell::C_eff});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_TRUE(std::isnan(c[0].Cb_over_Mbw.mean));
  EXPECT_DOUBLE_EQ(c[0].C_eff.mean, 2);
}

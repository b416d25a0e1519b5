#include "terratraj/search/reference_frames.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "search_fixtures.hpp"
#include "terratraj/terrain/obstacle_clusters.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::search {
namespace {

using Eigen::Vector2d;
using Polyline = std::vector<Vector2d>;

// A flat 40 m x 40 m map of 0.5 m cells with a (zero) lethal layer.
terrain::ElevationMap emptyMap() {
  terrain::GridGeometry g;
  g.rows = g.cols = 80;
  g.cell = 0.5;
  terrain::ElevationMap map(g);
  map.addLayer(terrain::layer_names::kLethal);
  return map;
}

// Marks lethal the cells covering [x0, x1] x [y0, y1] [m] (cell edges on those lines).
void addBlock(terrain::ElevationMap& map, double x0, double y0, double x1, double y1) {
  terrain::GridLayer& lethal = *map.findLayer(terrain::layer_names::kLethal);
  const terrain::GridGeometry& g = map.geometry();
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const Vector2d centre = g.cellCenter({r, c});
      if (centre.x() > x0 && centre.x() < x1 && centre.y() > y0 && centre.y() < y1) {
        lethal(r, c) = 1.0f;
      }
    }
  }
}

ReferenceFrames framesOf(const terrain::ElevationMap& map, const Vector2d& anchor,
                         double radius = 10.0) {
  ReferenceFrameOptions options;
  options.anchor = anchor;
  options.frame_radius = radius;
  return ReferenceFrames::build(map, terrain::findObstacleClusters(map), options);
}

void expectPoint(const Vector2d& actual, const Vector2d& expected) {
  EXPECT_NEAR(actual.x(), expected.x(), 1e-9);
  EXPECT_NEAR(actual.y(), expected.y(), 1e-9);
}

// One 4 m block centred at (20, 20), anchor (10, 20): frame a from (22, 20) east to the edge.
class ReferenceFramesOneBlock : public ::testing::Test {
 protected:
  ReferenceFramesOneBlock() : map(emptyMap()) {
    addBlock(map, 18.0, 18.0, 22.0, 22.0);
    frames = framesOf(map, {10.0, 20.0});
  }
  std::string signature(const Polyline& path) const { return frames.signatureOf(path).toString(); }
  terrain::ElevationMap map;
  ReferenceFrames frames;
};

TEST_F(ReferenceFramesOneBlock, FrameRunsFromTheFarSideToTheMapEdge) {
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames.frames()[0].cluster, 0);
  expectPoint(frames.frames()[0].start, {22.0, 20.0});
  expectPoint(frames.frames()[0].end, {40.0, 20.0});
  expectPoint(frames.anchor(), {10.0, 20.0});
}

TEST_F(ReferenceFramesOneBlock, PathsOnDifferentSidesGetDifferentSignatures) {
  const Polyline north{{10, 20}, {15, 25}, {25, 25}, {30, 21}};
  const Polyline south{{10, 20}, {15, 15}, {25, 15}, {30, 21}};
  EXPECT_EQ(signature(north), "");
  EXPECT_EQ(signature(south), "a+");
  // Driven backwards the crossing changes direction.
  EXPECT_EQ(signature({{30, 21}, {25, 15}, {15, 15}, {10, 20}}), "a-");
}

TEST_F(ReferenceFramesOneBlock, WigglesAndRecrossingsOnOneSideKeepTheSignature) {
  EXPECT_EQ(signature({{10, 20}, {15, 25}, {18, 26}, {20, 24.5}, {22, 27}, {25, 25}, {30, 21}}),
            "");
  EXPECT_EQ(signature({{10, 20}, {15, 15}, {20, 16}, {23, 14}, {25, 15}, {30, 21}}), "a+");
  // South path that crosses into the north and back before its final crossing.
  EXPECT_EQ(signature({{10, 20}, {15, 15}, {25, 15}, {27, 23}, {28, 17}, {30, 21}}), "a+");
  // North path that dips across the frame and back.
  EXPECT_EQ(signature({{10, 20}, {15, 25}, {25, 25}, {26, 18}, {27, 24}, {30, 21}}), "");
}

TEST_F(ReferenceFramesOneBlock, VertexOnTheFrameCountsOnce) {
  EXPECT_EQ(signature({{25, 15}, {26, 20}, {27, 25}}), "a+");
  EXPECT_EQ(signature({{27, 25}, {26, 20}, {25, 15}}), "a-");
  // Touching the frame and going back: nothing.
  EXPECT_EQ(signature({{25, 15}, {26, 20}, {27, 15}}), "");
  EXPECT_EQ(signature({{25, 25}, {26, 20}, {27, 25}}), "");
  // Two vertices on the frame, sliding along it, then leaving to the other side.
  EXPECT_EQ(signature({{25, 15}, {26, 20}, {28, 20}, {29, 25}}), "a+");
  EXPECT_EQ(signature({{25, 25}, {26, 20}, {28, 20}, {29, 15}}), "a-");
  // The frame's start is in [0, length), its end is not: through (40, 20) nothing counts.
  EXPECT_EQ(signature({{39.9, 19}, {40, 20}, {39.9, 21}}), "");
  // Beyond the block on the near side (between anchor and block) there is no frame.
  EXPECT_EQ(signature({{15, 15}, {15, 25}}), "");
}

// Goal (30, 20) on frame a. Routes that stop near it (a goal region, a solver's tolerance) a
// hair on either side of the frame differ by one crossing when open; closed at the exact goal
// they get their route's class: north "" and south "a+".
TEST_F(ReferenceFramesOneBlock, PathsClosedAtTheGoalGetTheirRoutesClassWhenAFramePassesIt) {
  const Vector2d start(10, 20);
  const Vector2d goal(30, 20);
  const Polyline north_on{{10, 20}, {15, 25}, {25, 25}, {29.5, 20}};
  const Polyline north_below{{10, 20}, {15, 25}, {25, 25}, {29.5, 20}, {29.999, 19.999999}};
  const Polyline south_below{{10, 20}, {15, 15}, {25, 15}, {29.5, 19.5}};
  const Polyline south_on{{10, 20}, {15, 15}, {25, 15}, {29.5, 19.5}, {29.9, 20}};
  EXPECT_EQ(signature(north_on), "");
  EXPECT_EQ(signature(north_below), "a-");
  EXPECT_EQ(signature(south_below), "");
  EXPECT_EQ(signature(south_on), "a+");
  for (const Polyline& north : {north_on, north_below}) {
    EXPECT_EQ(frames.signatureBetween(start, north, goal).toString(), "");
  }
  for (const Polyline& south : {south_on, south_below}) {
    EXPECT_EQ(frames.signatureBetween(start, south, goal).toString(), "a+");
  }
  // Closed at the start too: from (35, 21), north of the frame, to a path south of it.
  EXPECT_EQ(frames.signatureOf({{35, 19}, {30, 18}}).toString(), "");
  EXPECT_EQ(frames.signatureBetween({35, 21}, {{35, 19}, {30, 18}}, {25, 18}).toString(), "a-");
  // No vertices: the segment start -> goal.
  EXPECT_EQ(frames.signatureBetween({25, 15}, {}, {25, 25}).toString(), "a+");
}

TEST_F(ReferenceFramesOneBlock, SegmentsOffTheFramesAddNothing) {
  HomotopySignature s;
  frames.appendCrossings({1, 1}, {1.3, 1.2}, s);
  frames.appendCrossings({30, 25}, {30.2, 25.1}, s);
  frames.appendCrossings({30, 20}, {30, 20}, s);  // a point on the frame
  const double nan = std::numeric_limits<double>::quiet_NaN();
  frames.appendCrossings({nan, 0}, {30, 15}, s);
  frames.appendCrossings({-100, 10}, {-90, 30}, s);  // off the map
  EXPECT_TRUE(s.empty());
  // Short segments across the frame, also across bucket borders.
  for (double x = 22.05; x < 40.0; x += 0.37) {
    HomotopySignature one;
    frames.appendCrossings({x, 19.8}, {x + 0.1, 20.2}, one);
    EXPECT_EQ(one.toString(), "a+") << x;
  }
}

TEST(ReferenceFrames, DiagonalRayThroughCellCorners) {
  terrain::ElevationMap map = emptyMap();
  addBlock(map, 19.0, 19.0, 21.0, 21.0);
  const ReferenceFrames frames = framesOf(map, {10.0, 10.0}, 15.0);
  ASSERT_EQ(frames.size(), 1u);
  expectPoint(frames.frames()[0].start, {21.0, 21.0});
  expectPoint(frames.frames()[0].end, {40.0, 40.0});
  // Passing north-west of the block and ending south-east of the frame crosses it clockwise.
  EXPECT_EQ(frames.signatureOf({{10, 10}, {15, 25}, {30, 25}}).toString(), "a-");
  EXPECT_EQ(frames.signatureOf({{10, 10}, {25, 15}, {30, 25}}).toString(), "");
}

TEST(ReferenceFrames, NoLethalCellsMeansNoFrames) {
  terrain::GridGeometry g;
  g.rows = g.cols = 40;
  const terrain::ElevationMap without_layer(g);
  const ReferenceFrames none = framesOf(without_layer, {20.0, 20.0});
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(none.size(), 0u);
  EXPECT_TRUE(none.signatureOf({{0, 0}, {40, 40}, {0, 40}, {40, 0}}).empty());
  EXPECT_TRUE(framesOf(emptyMap(), {20.0, 20.0}).empty());
  // A default-built set answers too.
  EXPECT_TRUE(ReferenceFrames().signatureOf({{0, 0}, {1, 1}}).empty());
}

TEST(ReferenceFrames, FrameRadiusExcludesFarClusters) {
  terrain::ElevationMap map = emptyMap();
  addBlock(map, 24.0, 19.0, 26.0, 21.0);  // centroid 5 m east of the anchor: cluster 0
  addBlock(map, 19.0, 34.0, 21.0, 36.0);  // centroid 15 m north: cluster 1
  const ReferenceFrames near = framesOf(map, {20.0, 20.0}, 10.0);
  ASSERT_EQ(near.size(), 1u);
  EXPECT_EQ(near.frames()[0].cluster, 0);
  const ReferenceFrames both = framesOf(map, {20.0, 20.0}, 15.0);  // borders included
  ASSERT_EQ(both.size(), 2u);
  EXPECT_EQ(both.frames()[1].cluster, 1);
  expectPoint(both.frames()[1].start, {20.0, 36.0});
  expectPoint(both.frames()[1].end, {20.0, 40.0});
  EXPECT_TRUE(framesOf(map, {20.0, 20.0}, 4.0).empty());
  EXPECT_TRUE(framesOf(map, {20.0, 20.0}, 0.0).empty());
  EXPECT_TRUE(framesOf(map, {20.0, 20.0}, -1.0).empty());
  EXPECT_TRUE(framesOf(map, {20.0, std::numeric_limits<double>::quiet_NaN()}).empty());
}

TEST(ReferenceFrames, FramesEndAtTheNextObstacleOrNoDataOrTheEdge) {
  terrain::ElevationMap map = emptyMap();
  addBlock(map, 24.0, 19.0, 26.0, 21.0);  // A, on the ray east of the anchor
  addBlock(map, 31.0, 19.0, 33.0, 21.0);  // B, behind A on the same ray
  // A no-data cell north of the anchor, on the ray through block C.
  addBlock(map, 19.0, 24.0, 21.0, 26.0);  // C
  map.elevation()(66, 40) =
      std::numeric_limits<float>::quiet_NaN();  // cell [20, 20.5] x [33, 33.5]
  const ReferenceFrames frames = framesOf(map, {20.0, 20.0}, 20.0);
  ASSERT_EQ(frames.size(), 3u);
  // Clusters in row-major order of their first cell: A (row 38), B (row 38, further east), C.
  expectPoint(frames.frames()[0].start, {26.0, 20.0});
  expectPoint(frames.frames()[0].end, {31.0, 20.0});  // at B
  expectPoint(frames.frames()[1].start, {33.0, 20.0});
  expectPoint(frames.frames()[1].end, {40.0, 20.0});  // at the edge
  expectPoint(frames.frames()[2].start, {20.0, 26.0});
  expectPoint(frames.frames()[2].end, {20.0, 33.0});  // at the no-data cell
  // Passing between A and B crosses nothing: frame a ends at B.
  EXPECT_EQ(frames.signatureOf({{28, 15}, {28, 22}}).toString(), "a+");
  EXPECT_EQ(frames.signatureOf({{34, 15}, {34, 22}}).toString(), "b+");
  EXPECT_EQ(frames.signatureOf({{22, 30}, {18, 30}}).toString(), "c+");
}

TEST(ReferenceFrames, ClustersAtTheAnchorOrTheEdgeGetNoFrame) {
  terrain::ElevationMap map = emptyMap();
  addBlock(map, 4.0, 4.0, 6.0, 6.0);      // cluster 0: holds the anchor (5.2, 4.6) below
  addBlock(map, 28.0, 11.0, 32.0, 15.0);  // cluster 1: a ring around (30, 13) ...
  terrain::GridLayer& lethal = *map.findLayer(terrain::layer_names::kLethal);
  for (int r : {25, 26}) {
    for (int c : {59, 60}) lethal(r, c) = 0.0f;  // ... with a 1 m hole in its middle
  }
  addBlock(map, 36.0, 19.0, 40.0, 21.0);  // cluster 2: touches the east edge on its far side
  const std::vector<terrain::ObstacleCluster> clusters = terrain::findObstacleClusters(map);
  ASSERT_EQ(clusters.size(), 3u);

  const ReferenceFrames from_middle = framesOf(map, {30.0, 20.0}, 9.0);
  ASSERT_EQ(from_middle.size(), 1u);  // the ring's; the edge block gets none
  EXPECT_EQ(from_middle.frames()[0].cluster, 1);
  // The ray meets the ring twice: the frame starts on the ring's far wall.
  expectPoint(from_middle.frames()[0].start, {30.0, 11.0});
  expectPoint(from_middle.frames()[0].end, {30.0, 0.0});

  EXPECT_TRUE(framesOf(map, {5.2, 4.6}, 3.0).empty());    // anchor inside the block
  EXPECT_TRUE(framesOf(map, {30.0, 13.0}, 3.0).empty());  // the ring's centroid is the anchor
}

// Crossings by brute force over frames(), the documented rule, for random segments.
HomotopySignature bruteForce(const ReferenceFrames& frames, const Polyline& path) {
  HomotopySignature signature;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Vector2d p = path[i - 1], q = path[i];
    struct Hit {
      double u;
      int frame;
      int direction;
    };
    std::vector<Hit> hits;
    for (std::size_t f = 0; f < frames.size(); ++f) {
      const ReferenceFrame& frame = frames.frames()[f];
      const Vector2d d = (frame.end - frame.start) / frame.length();
      const auto side = [&](const Vector2d& x) {
        const Vector2d r = x - frame.start;
        return d.x() * r.y() - d.y() * r.x();
      };
      const double sp = side(p), sq = side(q);
      if ((sp >= 0) == (sq >= 0)) continue;
      const double u = sp / (sp - sq);
      const double along = d.dot(p + u * (q - p) - frame.start);
      if (along >= 0 && along < frame.length()) {
        hits.push_back({u, static_cast<int>(f), sq >= 0 ? +1 : -1});
      }
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.u < b.u; });
    for (const Hit& h : hits) signature.append({h.frame, h.direction});
  }
  return signature;
}

TEST(ReferenceFrames, ForestFramesOnlyForClustersWithinTheRadius) {
  const terrain::ElevationMap map = testing::generated(terrain::TerrainKind::kForest, 160, 3);
  const std::vector<terrain::ObstacleCluster> clusters = terrain::findObstacleClusters(map);
  const Vector2d anchor(20.0, 20.0);
  ReferenceFrameOptions options;
  options.anchor = anchor;
  options.frame_radius = 6.0;
  const ReferenceFrames frames = ReferenceFrames::build(map, clusters, options);

  std::size_t within = 0;
  for (const terrain::ObstacleCluster& c : clusters) within += (c.centroid - anchor).norm() <= 6.0;
  ASSERT_GT(frames.size(), 2u);
  EXPECT_LE(frames.size(), within);
  EXPECT_LT(frames.size(), clusters.size());

  const terrain::GridGeometry& g = map.geometry();
  const auto blocked = [&](const Vector2d& x) {
    const auto cell = g.cellAt(x);
    return !cell || map.isLethal(*cell) || map.isNoData(*cell);
  };
  int previous = -1;
  for (const ReferenceFrame& frame : frames.frames()) {
    const terrain::ObstacleCluster& cluster = clusters[static_cast<std::size_t>(frame.cluster)];
    EXPECT_GT(frame.cluster, previous);  // cluster order
    previous = frame.cluster;
    EXPECT_LE((cluster.centroid - anchor).norm(), 6.0);
    // On the ray from the anchor through the centroid, beyond the cluster.
    const Vector2d ray = (cluster.centroid - anchor).normalized();
    const Vector2d d = (frame.end - frame.start) / frame.length();
    EXPECT_NEAR(ray.dot(d), 1.0, 1e-9);
    EXPECT_NEAR(ray.x() * (frame.start - anchor).y() - ray.y() * (frame.start - anchor).x(), 0.0,
                1e-9);
    // Just before the start: a cell of the cluster; inside: free; just after the end: blocked.
    const auto before = g.cellAt(frame.start - 1e-6 * d);
    ASSERT_TRUE(before.has_value());
    bool member = false;
    for (const terrain::CellIndex& c : cluster.cells) member = member || c == *before;
    EXPECT_TRUE(member) << "frame of cluster " << frame.cluster;
    for (double s = 1e-6; s < frame.length() - 1e-6; s += 0.05) {
      EXPECT_FALSE(blocked(frame.start + s * d)) << frame.cluster << " at " << s;
    }
    EXPECT_TRUE(blocked(frame.end + 1e-6 * d));
  }
  // A larger radius gives more frames.
  options.frame_radius = 12.0;
  EXPECT_GT(ReferenceFrames::build(map, clusters, options).size(), frames.size());
}

TEST(ReferenceFrames, BucketGridMatchesBruteForceAndLongSegmentsMatchShortOnes) {
  const terrain::ElevationMap map = testing::generated(terrain::TerrainKind::kForest, 160, 5);
  const ReferenceFrames frames = framesOf(map, {20.0, 20.0}, 12.0);
  ASSERT_GT(frames.size(), 9u);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(0.0, 40.0);
  std::uniform_real_distribution<double> step(-0.4, 0.4);
  for (int trial = 0; trial < 200; ++trial) {
    // A random walk of short steps, and its own vertices joined by long straight segments.
    Polyline walk{{coordinate(random), coordinate(random)}};
    for (int i = 0; i < 300; ++i)
      walk.push_back(walk.back() + Vector2d(step(random), step(random)));
    EXPECT_EQ(frames.signatureOf(walk), bruteForce(frames, walk)) << trial;
    const Polyline jumps{walk.front(),
                         {coordinate(random), coordinate(random)},
                         {coordinate(random), coordinate(random)},
                         walk.back()};
    EXPECT_EQ(frames.signatureOf(jumps), bruteForce(frames, jumps)) << trial;
  }
}

TEST(ReferenceFrames, LongSegmentThroughManyFramesEqualsItsPieces) {
  // 36 single lethal cells on a circle of 8 m around the anchor: 36 frames to the map edge.
  terrain::ElevationMap map = emptyMap();
  terrain::GridLayer& lethal = *map.findLayer(terrain::layer_names::kLethal);
  for (int k = 0; k < 36; ++k) {
    const double angle = k * 10.0 * 3.14159265358979323846 / 180.0;
    const auto cell = map.geometry().cellAt(
        Vector2d(20.0 + 8.0 * std::cos(angle) + 0.01, 20.0 + 8.0 * std::sin(angle) + 0.01));
    lethal(*cell) = 1.0f;
  }
  const ReferenceFrames frames = framesOf(map, {20.0, 20.0}, 10.0);
  ASSERT_EQ(frames.size(), 36u);
  std::size_t most = 0;
  for (double y : {1.0, 2.5, 37.5, 39.0}) {
    const Vector2d p(0.3, y), q(39.7, y + 0.3);
    Polyline pieces;
    for (int i = 0; i <= 200; ++i) pieces.push_back(p + (q - p) * (i / 200.0));
    const HomotopySignature whole = frames.signatureOf({p, q});
    EXPECT_EQ(whole, frames.signatureOf(pieces)) << y;
    EXPECT_EQ(whole, bruteForce(frames, {p, q})) << y;
    most = std::max(most, whole.size());
  }
  EXPECT_GT(most, 8u);  // more crossings than the sorting buffer holds
}

}  // namespace
}  // namespace terratraj::search

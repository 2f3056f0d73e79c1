// Navigation mesh over RecastNavigation (Recast builds it, Detour stores and queries it).
//
// Every function of this header takes and returns world coordinates, which are z-up. Recast and
// Detour are y-up: the two inline functions below are the only place where one frame is turned
// into the other.
#pragma once

#include <DetourNavMesh.h>
#include <DetourNavMeshQuery.h>

#include "polyanya.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace navverse {

// An error the user can fix (bad input, nothing walkable, foreign file). Python sees NavMeshError.
class NavError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// World (x, y, z), z up  ->  Recast (x, y, z), y up: a rotation of -90 degrees about x, so
// handedness, triangle winding and normals are kept: (x, y, z) -> (x, z, -y).
inline void toRecast(const double* w, float* r) {
  r[0] = static_cast<float>(w[0]);
  r[1] = static_cast<float>(w[2]);
  r[2] = static_cast<float>(-w[1]);
}

// Recast (x, y, z) -> world (x, -z, y).
inline void fromRecast(const float* r, double* w) {
  w[0] = r[0];
  w[1] = -static_cast<double>(r[2]);
  w[2] = r[1];
}

using Vec3 = std::array<double, 3>;

// Build parameters, in the units of navverse.nav.NavMeshSettings (meters, degrees, cells).
struct BuildConfig {
  double cell_size = 0.05;
  double cell_height = 0.05;
  double agent_height = 0.6;
  double agent_radius = 0.6;
  double agent_max_climb = 0.2;
  double agent_max_slope = 45.0;
  double region_min_size = 8.0;
  double region_merge_size = 0.0;
  double edge_max_len = 0.0;
  double edge_max_error = 1.5;
  int verts_per_poly = 6;
  double detail_sample_dist = 1.0;
  double detail_sample_max_error = 0.0;
  bool filter_low_hanging_obstacles = true;
  bool filter_ledge_spans = true;
  bool filter_walkable_low_height_spans = true;
  bool fill_solid_interiors = true;
  int tile_size = 0;
  // Tiled builds only: the tiles whose area meets this world xy rectangle (xmin, ymin, xmax, ymax;
  // z up) are built with cells fine_factor times smaller in size and height.
  std::optional<std::array<double, 4>> fine_region;
  int fine_factor = 1;
};

// Triangle soup in world coordinates plus one area id per triangle (0 = never walkable).
struct InputMesh {
  std::vector<double> vertices;   // 3 * nverts, z-up
  std::vector<int> triangles;     // 3 * ntris
  std::vector<unsigned char> areas;  // ntris
};

// How path lengths follow the surface: a height sample every `step` meters, height wiggles below
// `tolerance` (voxel quantization) ignored.
struct LengthSampling {
  double step = 0.1;
  double tolerance = 0.075;
};

struct PathResult {
  std::vector<Vec3> points;  // empty when unreachable
  double length = 0.0;       // +inf when unreachable
  int end_index = -1;        // the goal reached, for multi-goal queries
};

struct TopDown {
  std::vector<std::uint8_t> mask;  // rows * cols, row 0 = largest y
  int rows = 0;
  int cols = 0;
  double origin_x = 0.0;  // world x of the left image edge
  double origin_y = 0.0;  // world y of the top image edge
};

class NavMesh {
 public:
  // Takes ownership of `mesh` (allocated with dtAllocNavMesh, tiles added).
  explicit NavMesh(dtNavMesh* mesh);
  ~NavMesh();
  NavMesh(const NavMesh&) = delete;
  NavMesh& operator=(const NavMesh&) = delete;

  // The Detour mesh itself, for a user that keeps its own copy (a Crowd sets its polygon flags).
  dtNavMesh* detour() { return nav_; }

  // --- serialization: Detour tile data plus their references ---
  std::string toBytes() const;
  static NavMesh* fromBytes(const std::string& blob);

  // --- query filter: per-area costs and excluded areas (path queries only) ---
  void setAreaCosts(const std::vector<double>& costs);  // DT_MAX_AREAS entries
  void setExcludedAreas(const std::vector<int>& areas);
  void setLengthSampling(double step, double tolerance);

  // --- point queries; `hext`/`vext` are the horizontal/vertical half sizes of the search box ---
  bool snap(const Vec3& p, double hext, double vext, bool pathFilter, dtPolyRef* ref, float* rc) const;
  bool isNavigable(const Vec3& p, double maxDz) const;
  int islandOf(const Vec3& p, double hext, double vext) const;
  double distanceToWall(const Vec3& p, double radius, double hext, double vext) const;

  // --- paths ---
  PathResult findPath(const Vec3& start, const Vec3& end, double hext, double vext) const;
  PathResult findPathMulti(const Vec3& start, const std::vector<Vec3>& ends, double hext, double vext) const;

  // --- random points, area-weighted uniform; NaN when nothing can be sampled ---
  Vec3 randomPoint(std::uint64_t seed, int island) const;
  Vec3 randomPointNear(const Vec3& center, double radius, std::uint64_t seed, int maxTries, double hext,
                       double vext) const;

  // --- whole-mesh information ---
  int numIslands() const { return static_cast<int>(islandArea_.size()); }
  const std::vector<double>& islandAreas() const { return islandArea_; }
  double navigableArea() const { return totalArea_; }
  int numTiles() const { return numTiles_; }
  int numPolygons() const { return numPolys_; }
  std::array<double, 6> bounds() const;  // xmin, ymin, zmin, xmax, ymax, zmax
  void polygons(std::vector<std::vector<Vec3>>* polys, std::vector<unsigned char>* areas) const;
  // Polygon edges with nothing walkable across them (no neighbour, no link to another tile).
  std::vector<std::array<Vec3, 2>> boundaryEdges() const;
  TopDown topDown(double metersPerPixel, bool useHeight, double height, double eps) const;

 private:
  void index();  // islands, areas, sampling tables and the path search index, after every build or load
  void updateUniform();
  // Shortest path between located points: exact (Polyanya) when every area costs 1 and none is
  // excluded, else Detour's A* with shortcut passes.
  PathResult shortestPath(dtPolyRef sRef, const float* s, dtPolyRef eRef, const float* e) const;
  int islandOfRef(dtPolyRef ref) const;
  double polyArea(const dtMeshTile* tile, int polyIndex) const;
  bool sampleInPoly(const dtMeshTile* tile, int polyIndex, double u, double v, double w, float* out) const;
  void resetFlags();

  dtNavMesh* nav_ = nullptr;
  dtNavMeshQuery* query_ = nullptr;
  dtQueryFilter pathFilter_;
  dtQueryFilter allFilter_;
  std::vector<bool> excluded_;

  mutable std::vector<dtPolyRef> polyBuf_;
  std::vector<int> tileBase_;    // per tile index: offset of its polygons in polyIsland_
  std::vector<int> polyIsland_;  // island of each polygon
  std::vector<bool> polyLevel_;  // whether each polygon is level (flat index)
  std::vector<double> islandArea_;
  // Detail triangles sorted by island; cumulative areas for area-weighted sampling.
  struct TriRef {
    dtPolyRef poly;
    int tri;
  };
  std::vector<TriRef> tris_;
  std::vector<double> triCum_;          // inclusive prefix sums of triangle areas, per island range
  std::vector<std::size_t> islandTri_;  // islandTri_[i] .. islandTri_[i+1]: triangles of island i
  double totalArea_ = 0.0;
  float climb_ = 0.0f;  // walkable climb (m), from the tiles
  bool uniformCosts_ = true;
  Polyanya polyanya_;
  LengthSampling sampling_;
  int numTiles_ = 0;
  int numPolys_ = 0;
  float bmin_[3] = {0, 0, 0};
  float bmax_[3] = {0, 0, 0};
};

// A navmesh build, prepared tile by tile so finished tiles of an earlier build can be reused.
//
// The constructor prepares the geometry (slopes, the tile grid, each tile's triangles); tileKey
// gives the bytes a tile's result depends on (its voxel grid, the settings that reach it, and its
// triangles with their area types, in order), so two tiles with equal keys build to equal data;
// build builds every tile that `reuse` does not supply and packs them into one navmesh. Throws
// NavError when nothing is walkable.
class TiledBuild {
 public:
  TiledBuild(InputMesh mesh, const BuildConfig& cfg);
  ~TiledBuild();
  TiledBuild(const TiledBuild&) = delete;
  TiledBuild& operator=(const TiledBuild&) = delete;

  int numTiles() const;
  // Empty for a tile that no triangle reaches (it is empty whatever else changes).
  std::string tileKey(int tile) const;
  // reuse: one entry per tile, the data an earlier build made for the same key ("" for a tile
  // that built empty) or nullopt to build it here; entries that are not a Detour tile of this
  // tile's position are built. built (optional): set per tile to the data built here ("" when
  // empty), nullopt for reused tiles and tiles without triangles. Runs tiles on up to `jobs`
  // threads; call without holding the Python GIL.
  NavMesh* build(int jobs, const std::vector<std::optional<std::string>>& reuse,
                 std::vector<std::optional<std::string>>* built);

  struct State;

 private:
  std::unique_ptr<State> state_;
};

// Builds a tiled (cfg.tile_size > 0) or single-tile navmesh, every tile anew (TiledBuild without reuse).
NavMesh* buildNavMesh(const InputMesh& mesh, const BuildConfig& cfg, int jobs);

}  // namespace navverse

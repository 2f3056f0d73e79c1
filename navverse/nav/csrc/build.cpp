// Navmesh build: Recast voxelizes each tile's triangles, Detour packs the tiles into one dtNavMesh.
//
// Tiles are built independently (each sees its own triangles plus a border of
// agent_radius + 3 cells, so tiles agree along their edges) on up to `jobs` threads. A tile's
// voxel grid depends only on the mesh's lower corner, the settings and its own triangles (its
// heightfield ends the agent height above its highest vertex), so a tile whose input is unchanged
// builds to the same data and can be taken from an earlier build (TiledBuild, tileKey). Each thread
// keeps only the tile it is working on, so the memory in flight is bounded by `jobs` tiles; the
// finished tiles are added to the navmesh in tile order, which keeps polygon references (and so
// random sampling and saved files) independent of thread timing.
//
// Mixed resolution (BuildConfig::fine_region, fine_factor f > 1): the tiles whose area meets the
// region are voxelized with cells f times smaller (cs / f, ch / f), so tile_size * f cells per side,
// the integer parameters recomputed from the meters for those cells, and a border of their own
// walkableRadius + 3 cells. All tiles keep one width in meters (dtNavMeshParams::tileWidth); each
// Detour tile header carries its own cell size, and Detour links neighbouring tiles through the
// portal edges on their common border, where the cell boundaries of both resolutions coincide.
// The tile borders lie half a coarse cell from the mesh minimum; with an even f that is a whole
// number of fine cells, so in fine tiles surfaces at round coordinates (multiples of the fine cell
// size from the mesh minimum) lie on cell boundaries, where float rounding puts them in either
// cell (a fine cell of difference). Heights have no such constraint: a fine tile's height grid
// starts half a fine cell height below the mesh, so floors at round heights lie mid-cell there too.
#include <DetourCommon.h>
#include <DetourNavMeshBuilder.h>
#include <Recast.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <sstream>
#include <thread>

#include "navmesh.h"

namespace navverse {
namespace {

// Navmesh heights are lowered by this many cell heights from the voxel span tops (see buildTile).
constexpr float kHeightOffset = 0.5f;

// Collects Recast's warnings and errors, so a failing tile can say why.
class BuildContext : public rcContext {
 public:
  BuildContext() : rcContext(true) { enableTimer(false); }
  std::string messages;

 protected:
  void doLog(const rcLogCategory category, const char* msg, const int len) override {
    if (category == RC_LOG_ERROR || category == RC_LOG_WARNING) {
      if (!messages.empty()) messages += "; ";
      messages.append(msg, static_cast<std::size_t>(len));
    }
  }
};

struct HeightfieldDeleter {
  void operator()(rcHeightfield* p) const { rcFreeHeightField(p); }
};
struct CompactDeleter {
  void operator()(rcCompactHeightfield* p) const { rcFreeCompactHeightfield(p); }
};
struct ContourDeleter {
  void operator()(rcContourSet* p) const { rcFreeContourSet(p); }
};
struct PolyMeshDeleter {
  void operator()(rcPolyMesh* p) const { rcFreePolyMesh(p); }
};
struct DetailDeleter {
  void operator()(rcPolyMeshDetail* p) const { rcFreePolyMeshDetail(p); }
};

// Recast's integer parameters from the settings' meters/degrees/cells. The small epsilons keep
// e.g. 0.3 / 0.1 = 2.9999999999999996 from becoming a climb of 2 cells.
rcConfig baseConfig(const BuildConfig& s) {
  rcConfig c;
  std::memset(&c, 0, sizeof(c));
  c.cs = static_cast<float>(s.cell_size);
  c.ch = static_cast<float>(s.cell_height);
  c.walkableSlopeAngle = static_cast<float>(s.agent_max_slope);
  c.walkableHeight = static_cast<int>(std::ceil(s.agent_height / s.cell_height - 1e-6));
  c.walkableClimb = static_cast<int>(std::floor(s.agent_max_climb / s.cell_height + 1e-6));
  c.walkableRadius = static_cast<int>(std::ceil(s.agent_radius / s.cell_size - 1e-6));
  c.maxEdgeLen = static_cast<int>(std::floor(s.edge_max_len / s.cell_size + 1e-6));
  c.maxSimplificationError = static_cast<float>(s.edge_max_error);
  c.minRegionArea = static_cast<int>(std::lround(s.region_min_size * s.region_min_size));
  c.mergeRegionArea = static_cast<int>(std::lround(s.region_merge_size * s.region_merge_size));
  c.maxVertsPerPoly = s.verts_per_poly;
  // Below 0.9 cells the detail mesh only follows polygon outlines. Recast's own way to say so
  // (detailSampleDist = 0) loops forever in this Recast version (triangulateHull with an empty
  // hull, recastnavigation issue #650); a sample distance far larger than any tile is equivalent.
  c.detailSampleDist = s.detail_sample_dist < 0.9 ? 1.0e6f : static_cast<float>(s.cell_size * s.detail_sample_dist);
  c.detailSampleMaxError = static_cast<float>(s.cell_height * s.detail_sample_max_error);
  return c;
}

struct Geometry {
  std::vector<float> verts;           // Recast frame
  const std::vector<int>* tris = nullptr;
  std::vector<unsigned char> areas;   // after the slope test
  int nverts = 0;
  int ntris = 0;
  float bmin[3];
  float bmax[3];
};

struct Grid {
  int tilesX = 1;
  int tilesY = 1;
  int cellsX = 0;  // cells per tile along x (single tile: the whole width)
  int cellsY = 0;  // cells per tile along Recast z
  int border = 0;  // cells
  float tileW = 0;  // meters
  float tileH = 0;
  std::vector<unsigned char> fine;  // per tile: built with the fine cells
  double fineBorder = 0;            // meters, the fine tiles' border (0 without fine tiles)
  // Triangles per tile (CSR): tileTris[tileStart[t] .. tileStart[t+1]).
  std::vector<std::size_t> tileStart;
  std::vector<int> tileTris;
  // Per tile: the top of its heightfield, the highest vertex of its triangles plus the agent height
  // (a tile's voxels never depend on geometry that does not reach it, so tiles can be reused).
  std::vector<float> tileTop;
};

// The cells one tile is voxelized in: Recast's parameters, the tile's core cells and the border.
struct Resolution {
  rcConfig cfg;
  int cellsX = 0;
  int cellsY = 0;
  int border = 0;  // cells
  float ymin = 0;  // bottom of the heightfield (Recast y)
  bool fine = false;
};

struct TileOut {
  unsigned char* data = nullptr;
  int size = 0;
  int polys = 0;
  bool fine = false;
  std::string error;
};

// Triangles per tile: those whose bounds come within the border of the tile's core. The border in
// meters is the wider of the coarse and the fine one, so every tile sees all of its border; it is
// the coarse one, (ceil(r / cs) + 3) * cs, which holds the fine one, (ceil(f * r / cs) + 3) * cs / f.
void bucketTriangles(const Geometry& g, Grid& grid, float headroom) {
  const int ntiles = grid.tilesX * grid.tilesY;
  const double bw =
      std::max(static_cast<double>(grid.border) * (static_cast<double>(grid.tileW) / grid.cellsX), grid.fineBorder);
  const std::vector<int>& tris = *g.tris;
  std::vector<std::array<int, 4>> ranges(static_cast<std::size_t>(g.ntris));
  std::vector<std::size_t> counts(static_cast<std::size_t>(ntiles) + 1, 0);
  for (int t = 0; t < g.ntris; ++t) {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (int k = 0; k < 3; ++k) {
      const float* v = &g.verts[3 * static_cast<std::size_t>(tris[3 * t + k])];
      lo[0] = std::min(lo[0], static_cast<double>(v[0]));
      hi[0] = std::max(hi[0], static_cast<double>(v[0]));
      lo[1] = std::min(lo[1], static_cast<double>(v[2]));
      hi[1] = std::max(hi[1], static_cast<double>(v[2]));
    }
    auto clampTile = [](double x, int n) { return static_cast<int>(std::clamp(x, 0.0, n - 1.0)); };
    const double ox = g.bmin[0], oz = g.bmin[2];
    int x0 = clampTile(std::floor((lo[0] - bw - ox) / grid.tileW - 1e-4), grid.tilesX);
    int x1 = clampTile(std::floor((hi[0] + bw - ox) / grid.tileW + 1e-4), grid.tilesX);
    int y0 = clampTile(std::floor((lo[1] - bw - oz) / grid.tileH - 1e-4), grid.tilesY);
    int y1 = clampTile(std::floor((hi[1] + bw - oz) / grid.tileH + 1e-4), grid.tilesY);
    ranges[static_cast<std::size_t>(t)] = {x0, x1, y0, y1};
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) ++counts[static_cast<std::size_t>(y * grid.tilesX + x) + 1];
  }
  for (int i = 0; i < ntiles; ++i) counts[i + 1] += counts[i];
  grid.tileStart = counts;
  grid.tileTris.assign(counts[static_cast<std::size_t>(ntiles)], 0);
  std::vector<std::size_t> fill(counts.begin(), counts.end() - 1);
  for (int t = 0; t < g.ntris; ++t) {
    const auto& r = ranges[static_cast<std::size_t>(t)];
    for (int y = r[2]; y <= r[3]; ++y)
      for (int x = r[0]; x <= r[1]; ++x) grid.tileTris[fill[static_cast<std::size_t>(y * grid.tilesX + x)]++] = t;
  }
  grid.tileTop.assign(static_cast<std::size_t>(ntiles), g.bmin[1]);
  for (int i = 0; i < ntiles; ++i) {
    float top = -std::numeric_limits<float>::infinity();
    for (std::size_t k = grid.tileStart[static_cast<std::size_t>(i)]; k < grid.tileStart[static_cast<std::size_t>(i) + 1]; ++k) {
      const int t = grid.tileTris[k];
      for (int j = 0; j < 3; ++j) top = std::max(top, g.verts[3 * static_cast<std::size_t>(tris[3 * t + j]) + 1]);
    }
    if (top > -std::numeric_limits<float>::infinity()) grid.tileTop[static_cast<std::size_t>(i)] = top + headroom;
  }
}

// Recast voxelizes surfaces only, so the inside of a closed solid (a box standing on the floor)
// is open space, and the floor under it a walkable island. This fills, per column, every interval
// from a downward-facing surface (a solid's underside) up to where the solid ends (upward-facing
// surfaces, counted with a depth so overlapping solids work) with an unwalkable span. The filled
// span merges with the top surface's span and keeps its area, so the top of a box stays walkable.
// Columns are probed at a fixed off-center point, so edges of authored geometry (round
// coordinates, axis-aligned or diagonal) practically never pass through a probe and no surface is
// counted twice; tiles agree with a single-tile build. Coincident faces of different solids are
// all counted, so touching or overlapping solids fill as their union.
void fillSolidInteriors(rcContext* ctx, const Geometry& g, const std::vector<int>& tris, rcHeightfield& hf,
                        int mergeThr) {
  struct Crossing {
    long long key;  // height in 0.1 mm steps
    int dir;        // -1 entering a solid (underside), +1 leaving it (top)
    float h;
    int next;       // the column's previous crossing in `pool`, -1 for none
  };
  const int n = static_cast<int>(tris.size() / 3);
  const float cs = hf.cs, ics = 1.0f / hf.cs, ich = 1.0f / hf.ch;
  const float probe[2] = {0.3183f * cs, 0.5772f * cs};  // off-center, away from round coordinates
  // Only columns with two or more spans can hold a surface inside a solid (a solid's own top is
  // one of the spans): the others are skipped before any work.
  const std::size_t columns = static_cast<std::size_t>(hf.width) * static_cast<std::size_t>(hf.height);
  std::vector<unsigned char> layered(columns, 0);
  bool anyLayered = false;
  for (std::size_t c = 0; c < columns; ++c) {
    layered[c] = hf.spans[c] != nullptr && hf.spans[c]->next != nullptr;
    anyLayered = anyLayered || layered[c];
  }
  if (!anyLayered) return;
  // Crossings of every column in one pool, chained per column (no allocation per column).
  std::vector<int> head(columns, -1);
  std::vector<Crossing> pool;

  auto visit = [&](int t, bool downward, bool onlyMarked) {
    const float* v0 = &g.verts[3 * static_cast<std::size_t>(tris[3 * t])];
    const float* v1 = &g.verts[3 * static_cast<std::size_t>(tris[3 * t + 1])];
    const float* v2 = &g.verts[3 * static_cast<std::size_t>(tris[3 * t + 2])];
    const float xmin = std::min({v0[0], v1[0], v2[0]}), xmax = std::max({v0[0], v1[0], v2[0]});
    const float zmin = std::min({v0[2], v1[2], v2[2]}), zmax = std::max({v0[2], v1[2], v2[2]});
    const int x0 = std::max(0, static_cast<int>(std::floor((xmin - hf.bmin[0] - probe[0]) * ics)));
    const int x1 = std::min(hf.width - 1, static_cast<int>(std::floor((xmax - hf.bmin[0] - probe[0]) * ics)));
    const int z0 = std::max(0, static_cast<int>(std::floor((zmin - hf.bmin[2] - probe[1]) * ics)));
    const int z1 = std::min(hf.height - 1, static_cast<int>(std::floor((zmax - hf.bmin[2] - probe[1]) * ics)));
    const double d = static_cast<double>(v1[2] - v2[2]) * (v0[0] - v2[0]) + static_cast<double>(v2[0] - v1[0]) * (v0[2] - v2[2]);
    if (std::abs(d) < 1e-12) return;
    for (int z = z0; z <= z1; ++z) {
      const double pz = hf.bmin[2] + z * cs + probe[1];
      for (int x = x0; x <= x1; ++x) {
        const std::size_t c = static_cast<std::size_t>(x) + static_cast<std::size_t>(z) * static_cast<std::size_t>(hf.width);
        if (!layered[c] || (onlyMarked && head[c] < 0)) continue;
        const double px = hf.bmin[0] + x * cs + probe[0];
        const double l0 = ((v1[2] - v2[2]) * (px - v2[0]) + (v2[0] - v1[0]) * (pz - v2[2])) / d;
        const double l1 = ((v2[2] - v0[2]) * (px - v2[0]) + (v0[0] - v2[0]) * (pz - v2[2])) / d;
        const double l2 = 1.0 - l0 - l1;
        if (l0 < 0 || l1 < 0 || l2 < 0) continue;
        const double h = l0 * v0[1] + l1 * v1[1] + l2 * v2[1];
        pool.push_back({std::llround(h * 1e4), downward ? -1 : +1, static_cast<float>(h), head[c]});
        head[c] = static_cast<int>(pool.size()) - 1;
      }
    }
  };
  // Facing from the normal's y (e0 x e1, Recast's convention: up-facing floors have ny > 0).
  std::vector<signed char> facing(static_cast<std::size_t>(n), 0);
  for (int t = 0; t < n; ++t) {
    const float* v0 = &g.verts[3 * static_cast<std::size_t>(tris[3 * t])];
    const float* v1 = &g.verts[3 * static_cast<std::size_t>(tris[3 * t + 1])];
    const float* v2 = &g.verts[3 * static_cast<std::size_t>(tris[3 * t + 2])];
    float e0[3], e1[3], nrm[3];
    rcVsub(e0, v1, v0);
    rcVsub(e1, v2, v0);
    rcVcross(nrm, e0, e1);
    const float len = std::sqrt(rcVdot(nrm, nrm));
    if (len > 0 && std::abs(nrm[1]) > 1e-4f * len) facing[static_cast<std::size_t>(t)] = nrm[1] > 0 ? 1 : -1;
  }
  for (int t = 0; t < n; ++t)
    if (facing[static_cast<std::size_t>(t)] < 0) visit(t, true, false);
  if (pool.empty()) return;
  for (int t = 0; t < n; ++t)
    if (facing[static_cast<std::size_t>(t)] > 0) visit(t, false, true);

  const float top = hf.bmax[1] - hf.bmin[1];
  std::vector<Crossing> cr;
  for (int z = 0; z < hf.height; ++z) {
    for (int x = 0; x < hf.width; ++x) {
      int ci = head[static_cast<std::size_t>(x) + static_cast<std::size_t>(z) * static_cast<std::size_t>(hf.width)];
      if (ci < 0) continue;
      cr.clear();
      for (; ci >= 0; ci = pool[static_cast<std::size_t>(ci)].next) cr.push_back(pool[static_cast<std::size_t>(ci)]);
      // Upward through the column; at equal heights leave (tops) before entering (undersides), so
      // a box standing on a floor starts at the floor.
      std::sort(cr.begin(), cr.end(), [](const Crossing& a, const Crossing& b) {
        return a.key != b.key ? a.key < b.key : a.dir > b.dir;
      });
      int depth = 0;
      float start = 0;
      for (const Crossing& c : cr) {
        if (c.dir < 0) {
          if (depth++ == 0) start = c.h;
        } else if (depth > 0 && --depth == 0) {
          const float lo = start - hf.bmin[1], hi = std::min(c.h - hf.bmin[1], top);
          if (hi <= 0 || lo >= top) continue;
          const int smin = std::clamp(static_cast<int>(std::floor(lo * ich)), 0, RC_SPAN_MAX_HEIGHT);
          const int smax = std::clamp(static_cast<int>(std::ceil(hi * ich)), smin + 1, RC_SPAN_MAX_HEIGHT);
          rcAddSpan(ctx, hf, x, z, static_cast<unsigned short>(smin), static_cast<unsigned short>(smax), RC_NULL_AREA,
                    mergeThr);
        }
      }
    }
  }
}

// The voxel grid of one tile: its resolution's parameters and the tile's bounds with its border.
rcConfig tileConfig(const Geometry& g, const Grid& grid, const Resolution& res, int tx, int ty) {
  rcConfig c = res.cfg;
  c.tileSize = res.border > 0 ? res.cellsX : 0;
  c.borderSize = res.border;
  c.width = res.cellsX + 2 * res.border;
  c.height = res.cellsY + 2 * res.border;
  c.bmin[0] = g.bmin[0] + tx * grid.tileW - res.border * c.cs;
  c.bmin[1] = res.ymin;
  c.bmin[2] = g.bmin[2] + ty * grid.tileH - res.border * c.cs;
  c.bmax[0] = g.bmin[0] + (tx + 1) * grid.tileW + res.border * c.cs;
  c.bmax[1] = grid.tileTop[static_cast<std::size_t>(ty * grid.tilesX + tx)];
  c.bmax[2] = g.bmin[2] + (ty + 1) * grid.tileH + res.border * c.cs;
  return c;
}

TileOut buildTile(const Geometry& g, const Grid& grid, const Resolution& res, const BuildConfig& opts, int tx,
                  int ty) {
  TileOut out;
  out.fine = res.fine;
  const int tileIndex = ty * grid.tilesX + tx;
  const std::size_t begin = grid.tileStart[static_cast<std::size_t>(tileIndex)];
  const std::size_t end = grid.tileStart[static_cast<std::size_t>(tileIndex) + 1];
  if (begin == end) return out;

  BuildContext ctx;
  const rcConfig c = tileConfig(g, grid, res, tx, ty);

  auto fail = [&](const char* step) {
    std::ostringstream msg;
    msg << "tile (" << tx << ", " << ty << ")";
    if (res.fine) msg << " (fine, cell_size " << c.cs << " m)";
    msg << ": " << step << " failed";
    if (!ctx.messages.empty()) msg << " (" << ctx.messages << ")";
    out.error = msg.str();
    return out;
  };

  // Rasterize this tile's triangles.
  const std::size_t n = end - begin;
  std::vector<int> tris(3 * n);
  std::vector<unsigned char> areas(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int t = grid.tileTris[begin + i];
    std::memcpy(&tris[3 * i], &(*g.tris)[3 * static_cast<std::size_t>(t)], 3 * sizeof(int));
    areas[i] = g.areas[static_cast<std::size_t>(t)];
  }
  std::unique_ptr<rcHeightfield, HeightfieldDeleter> hf(rcAllocHeightfield());
  if (!hf || !rcCreateHeightfield(&ctx, *hf, c.width, c.height, c.bmin, c.bmax, c.cs, c.ch))
    return fail("creating the heightfield");
  if (!rcRasterizeTriangles(&ctx, g.verts.data(), g.nverts, tris.data(), areas.data(), static_cast<int>(n), *hf,
                            c.walkableClimb))
    return fail("rasterizing triangles");
  if (opts.fill_solid_interiors) fillSolidInteriors(&ctx, g, tris, *hf, c.walkableClimb);
  tris = {};
  areas = {};

  // Filter walkable spans: climbable obstacles, ledges, low ceilings.
  if (opts.filter_low_hanging_obstacles) rcFilterLowHangingWalkableObstacles(&ctx, c.walkableClimb, *hf);
  if (opts.filter_ledge_spans) rcFilterLedgeSpans(&ctx, c.walkableHeight, c.walkableClimb, *hf);
  if (opts.filter_walkable_low_height_spans) rcFilterWalkableLowHeightSpans(&ctx, c.walkableHeight, *hf);

  // Open space, eroded by the agent radius, split into regions.
  std::unique_ptr<rcCompactHeightfield, CompactDeleter> chf(rcAllocCompactHeightfield());
  if (!chf || !rcBuildCompactHeightfield(&ctx, c.walkableHeight, c.walkableClimb, *hf, *chf))
    return fail("building the compact heightfield");
  hf.reset();
  if (c.walkableRadius > 0 && !rcErodeWalkableArea(&ctx, c.walkableRadius, *chf))
    return fail("eroding by the agent radius");
  if (!rcBuildDistanceField(&ctx, *chf)) return fail("building the distance field");
  if (!rcBuildRegions(&ctx, *chf, c.borderSize, c.minRegionArea, c.mergeRegionArea))
    return fail("building regions");

  // Contours -> polygons -> detail (height) meshes.
  std::unique_ptr<rcContourSet, ContourDeleter> cset(rcAllocContourSet());
  if (!cset || !rcBuildContours(&ctx, *chf, c.maxSimplificationError, c.maxEdgeLen, *cset))
    return fail("tracing contours");
  if (cset->nconts == 0) return out;
  std::unique_ptr<rcPolyMesh, PolyMeshDeleter> pmesh(rcAllocPolyMesh());
  if (!pmesh || !rcBuildPolyMesh(&ctx, *cset, c.maxVertsPerPoly, *pmesh))
    return fail(res.fine ? "building polygons (a tile holds at most 65535 vertices: use a smaller tile_size or "
                           "fine_factor)"
                         : "building polygons (a tile holds at most 65535 vertices: use a smaller tile_size)");
  cset.reset();
  if (pmesh->npolys == 0) return out;
  std::unique_ptr<rcPolyMeshDetail, DetailDeleter> dmesh(rcAllocPolyMeshDetail());
  if (!dmesh || !rcBuildPolyMeshDetail(&ctx, *pmesh, *chf, c.detailSampleDist, c.detailSampleMaxError, *dmesh))
    return fail("building the detail mesh");
  chf.reset();
  // rcBuildPolyMeshDetail lifts every detail vertex by one cell height when moving it to world
  // space, while Detour takes polygon corners from the poly mesh without that lift: on a flat floor
  // the detail mesh would bulge one cell above its own corners (random points and snapped heights
  // off by up to a cell, areas inflated). Undo the lift so both share one reference, and lower
  // both by half a cell (kHeightOffset): a span's top is its surface rounded up to the next cell
  // boundary, and surfaces sit mid-cell on the half-cell-shifted grid, so this puts the navmesh on
  // the surface (unbiased: within half a cell height either way).
  for (int i = 0; i < dmesh->nverts; ++i) dmesh->verts[3 * i + 1] -= c.ch * (1.0f + kHeightOffset);

  // Every polygon is walkable (flag 1); its area id is the triangles' area type.
  for (int i = 0; i < pmesh->npolys; ++i) pmesh->flags[i] = pmesh->areas[i] != RC_NULL_AREA ? 1 : 0;

  dtNavMeshCreateParams p;
  std::memset(&p, 0, sizeof(p));
  p.verts = pmesh->verts;
  p.vertCount = pmesh->nverts;
  p.polys = pmesh->polys;
  p.polyAreas = pmesh->areas;
  p.polyFlags = pmesh->flags;
  p.polyCount = pmesh->npolys;
  p.nvp = pmesh->nvp;
  p.detailMeshes = dmesh->meshes;
  p.detailVerts = dmesh->verts;
  p.detailVertsCount = dmesh->nverts;
  p.detailTris = dmesh->tris;
  p.detailTriCount = dmesh->ntris;
  p.walkableHeight = static_cast<float>(c.walkableHeight * c.ch);
  p.walkableRadius = static_cast<float>(c.walkableRadius * c.cs);
  p.walkableClimb = static_cast<float>(c.walkableClimb * c.ch);
  p.tileX = tx;
  p.tileY = ty;
  p.tileLayer = 0;
  rcVcopy(p.bmin, pmesh->bmin);
  rcVcopy(p.bmax, pmesh->bmax);
  p.bmin[1] -= c.ch * kHeightOffset;  // polygon corners are bmin[1] + cells * ch
  p.bmax[1] -= c.ch * kHeightOffset;
  p.cs = c.cs;
  p.ch = c.ch;
  p.buildBvTree = true;
  if (!dtCreateNavMeshData(&p, &out.data, &out.size)) return fail("packing the Detour tile");
  out.polys = pmesh->npolys;
  return out;
}

std::string noWalkableMessage(const Geometry& g, int flatTriangles, int walkableTypeTriangles,
                              const BuildConfig& s) {
  std::ostringstream msg;
  msg << "no walkable surface: ";
  if (walkableTypeTriangles == 0) {
    msg << "all " << g.ntris << " triangles have area type 0 (never walkable); give floors a type in 1..62";
  } else if (flatTriangles == 0) {
    msg << "none of the " << walkableTypeTriangles << " walkable-type triangles faces up (+z) with a slope of at most "
        << s.agent_max_slope << " degrees; check that floors are wound counter-clockwise seen from above";
  } else {
    msg << flatTriangles << " of " << g.ntris << " triangles are flat enough, but no navmesh polygon remained after "
        << "requiring " << s.agent_height << " m of headroom, eroding by agent_radius " << s.agent_radius
        << " m and dropping regions smaller than region_min_size " << s.region_min_size
        << " cells; check the scene scale (meters) and the agent size";
  }
  return msg.str();
}

}  // namespace

// Everything a build needs between preparing the tiles and packing them.
struct TiledBuild::State {
  InputMesh mesh;
  BuildConfig settings;
  Geometry g;
  Grid grid;
  Resolution coarse;
  Resolution fine;
  int ntiles = 0;
  int tileBits = 0;
  int polyBits = 0;
  int flatTriangles = 0;
  int walkableTypeTriangles = 0;

  const Resolution& resolution(int tile) const { return grid.fine[static_cast<std::size_t>(tile)] ? fine : coarse; }
};

TiledBuild::TiledBuild(InputMesh input, const BuildConfig& s) : state_(std::make_unique<State>()) {
  State& st = *state_;
  st.mesh = std::move(input);
  st.settings = s;
  const InputMesh& mesh = st.mesh;
  Geometry& g = st.g;
  g.nverts = static_cast<int>(mesh.vertices.size() / 3);
  g.ntris = static_cast<int>(mesh.triangles.size() / 3);
  g.tris = &mesh.triangles;
  if (g.nverts == 0 || g.ntris == 0) throw NavError("no walkable surface: the mesh has no triangles");
  g.verts.resize(3 * static_cast<std::size_t>(g.nverts));
  for (int i = 0; i < g.nverts; ++i) toRecast(&mesh.vertices[3 * static_cast<std::size_t>(i)], &g.verts[3 * static_cast<std::size_t>(i)]);
  rcCalcBounds(g.verts.data(), g.nverts, g.bmin, g.bmax);
  // Shift the voxel grid by half a cell, so surfaces at round coordinates (multiples of the cell
  // size from the mesh's minimum, as in most authored scenes) fall in the middle of cells rather
  // than on cell boundaries, where float rounding would put them on either side -- differently in
  // a tile than in a single-tile build.
  g.bmin[0] -= 0.5f * static_cast<float>(s.cell_size);
  g.bmin[2] -= 0.5f * static_cast<float>(s.cell_size);
  g.bmin[1] -= 0.5f * static_cast<float>(s.cell_height);
  g.bmax[0] += 0.5f * static_cast<float>(s.cell_size);
  g.bmax[2] += 0.5f * static_cast<float>(s.cell_size);

  // Area ids per triangle; triangles steeper than the max slope (or facing down) become RC_NULL_AREA.
  g.areas = mesh.areas;
  for (unsigned char a : g.areas) st.walkableTypeTriangles += a != RC_NULL_AREA;
  BuildContext ctx;
  rcClearUnwalkableTriangles(&ctx, static_cast<float>(s.agent_max_slope), g.verts.data(), g.nverts,
                             mesh.triangles.data(), g.ntris, g.areas.data());
  for (unsigned char a : g.areas) st.flatTriangles += a != RC_NULL_AREA;
  if (st.flatTriangles == 0) throw NavError(noWalkableMessage(g, st.flatTriangles, st.walkableTypeTriangles, s));

  const rcConfig base = baseConfig(s);
  const int gw = std::max(1, static_cast<int>(std::ceil((g.bmax[0] - g.bmin[0]) / base.cs - 1e-4)));
  const int gh = std::max(1, static_cast<int>(std::ceil((g.bmax[2] - g.bmin[2]) / base.cs - 1e-4)));
  Grid& grid = st.grid;
  if (s.tile_size > 0) {
    grid.cellsX = grid.cellsY = s.tile_size;
    grid.tilesX = (gw + s.tile_size - 1) / s.tile_size;
    grid.tilesY = (gh + s.tile_size - 1) / s.tile_size;
    grid.border = base.walkableRadius + 3;
  } else {
    grid.cellsX = gw;
    grid.cellsY = gh;
  }
  grid.tileW = grid.cellsX * base.cs;
  grid.tileH = grid.cellsY * base.cs;
  const long long ntilesLL = static_cast<long long>(grid.tilesX) * grid.tilesY;
  st.tileBits = ntilesLL > 1 ? static_cast<int>(dtIlog2(dtNextPow2(static_cast<unsigned int>(std::min(ntilesLL, 1LL << 30))))) : 0;
  if (st.tileBits > 14) {
    std::ostringstream msg;
    msg << "the scene needs " << grid.tilesX << " x " << grid.tilesY << " tiles of tile_size " << s.tile_size
        << " cells, more than the 16384 Detour's 32-bit polygon references allow: increase tile_size";
    throw NavError(msg.str());
  }
  st.polyBits = 22 - st.tileBits;
  st.ntiles = static_cast<int>(ntilesLL);

  Resolution& coarse = st.coarse;
  coarse.cfg = base;
  coarse.cellsX = grid.cellsX;
  coarse.cellsY = grid.cellsY;
  coarse.border = grid.border;
  coarse.ymin = g.bmin[1];
  Resolution& fine = st.fine;
  fine = coarse;
  grid.fine.assign(static_cast<std::size_t>(st.ntiles), 0);
  if (s.tile_size > 0 && s.fine_factor > 1 && s.fine_region) {
    BuildConfig fs = s;
    fs.cell_size = s.cell_size / s.fine_factor;
    fs.cell_height = s.cell_height / s.fine_factor;
    fine.cfg = baseConfig(fs);
    fine.cellsX = fine.cellsY = s.tile_size * s.fine_factor;
    fine.border = fine.cfg.walkableRadius + 3;
    // Like the coarse grid, half a cell height (a fine one) below the lowest vertex.
    fine.ymin = g.bmin[1] + 0.5f * (base.ch - fine.cfg.ch);
    fine.fine = true;
    grid.fineBorder = static_cast<double>(fine.border) * (static_cast<double>(grid.tileW) / fine.cellsX);
    // The region in the Recast frame (x, z) = (world x, -world y); a tile is fine when its core
    // and the region overlap with a positive area.
    const std::array<double, 4>& r = *s.fine_region;
    const double rx0 = r[0], rx1 = r[2], rz0 = -r[3], rz1 = -r[1];
    for (int ty = 0; ty < grid.tilesY; ++ty) {
      const double z0 = g.bmin[2] + ty * static_cast<double>(grid.tileH), z1 = z0 + grid.tileH;
      for (int tx = 0; tx < grid.tilesX; ++tx) {
        const double x0 = g.bmin[0] + tx * static_cast<double>(grid.tileW), x1 = x0 + grid.tileW;
        grid.fine[static_cast<std::size_t>(ty * grid.tilesX + tx)] = rx0 < x1 && x0 < rx1 && rz0 < z1 && z0 < rz1;
      }
    }
  }
  bucketTriangles(g, grid, static_cast<float>(s.agent_height));
}

TiledBuild::~TiledBuild() = default;

int TiledBuild::numTiles() const { return state_->ntiles; }

std::string TiledBuild::tileKey(int tile) const {
  const State& st = *state_;
  if (tile < 0 || tile >= st.ntiles) throw NavError("tile index out of range");
  const std::size_t begin = st.grid.tileStart[static_cast<std::size_t>(tile)];
  const std::size_t end = st.grid.tileStart[static_cast<std::size_t>(tile) + 1];
  if (begin == end) return {};
  static_assert(sizeof(rcConfig) % 4 == 0, "rcConfig is read as plain 4-byte fields");
  const Resolution& res = st.resolution(tile);
  const rcConfig c = tileConfig(st.g, st.grid, res, tile % st.grid.tilesX, tile / st.grid.tilesX);
  const std::int32_t header[3] = {tile % st.grid.tilesX, tile / st.grid.tilesX, res.fine ? 1 : 0};
  const unsigned char flags[4] = {st.settings.filter_low_hanging_obstacles, st.settings.filter_ledge_spans,
                                  st.settings.filter_walkable_low_height_spans, st.settings.fill_solid_interiors};
  const float offset = kHeightOffset;
  std::string key;
  key.reserve(64 + sizeof(c) + (end - begin) * (9 * sizeof(float) + 1));
  auto put = [&key](const void* p, std::size_t n) { key.append(static_cast<const char*>(p), n); };
  put("navverse-tile-input", 19);
  put(header, sizeof(header));
  put(&c, sizeof(c));
  put(flags, sizeof(flags));
  put(&offset, sizeof(offset));
  const std::vector<int>& tris = *st.g.tris;
  for (std::size_t i = begin; i < end; ++i) {
    const int t = st.grid.tileTris[i];
    for (int k = 0; k < 3; ++k) put(&st.g.verts[3 * static_cast<std::size_t>(tris[3 * static_cast<std::size_t>(t) + k])], 3 * sizeof(float));
    put(&st.g.areas[static_cast<std::size_t>(t)], 1);
  }
  return key;
}

namespace {

// Tile data from an earlier build, copied into Detour's allocator, when it is a Detour tile of
// this position; an empty string is a tile that built empty. False when it cannot be used.
bool reuseTile(const std::string& data, int tx, int ty, bool fine, TileOut& out) {
  out = TileOut();
  out.fine = fine;
  if (data.empty()) return true;
  if (data.size() < sizeof(dtMeshHeader)) return false;
  dtMeshHeader header;
  std::memcpy(&header, data.data(), sizeof(header));
  if (header.magic != DT_NAVMESH_MAGIC || header.version != DT_NAVMESH_VERSION || header.x != tx || header.y != ty ||
      header.layer != 0)
    return false;
  out.data = static_cast<unsigned char*>(dtAlloc(data.size(), DT_ALLOC_PERM));
  if (!out.data) throw std::bad_alloc();
  std::memcpy(out.data, data.data(), data.size());
  out.size = static_cast<int>(data.size());
  out.polys = header.polyCount;
  return true;
}

}  // namespace

NavMesh* TiledBuild::build(int jobs, const std::vector<std::optional<std::string>>& reuse,
                           std::vector<std::optional<std::string>>* built) {
  State& st = *state_;
  const Geometry& g = st.g;
  const Grid& grid = st.grid;
  const BuildConfig& s = st.settings;
  const int ntiles = st.ntiles;
  if (!reuse.empty() && static_cast<int>(reuse.size()) != ntiles) throw NavError("reuse needs one entry per tile");

  // Reused tiles first; the others are built: at most `jobs` threads, each holding one tile at a time.
  std::vector<TileOut> tiles(static_cast<std::size_t>(ntiles));
  std::vector<int> todo;
  for (int i = 0; i < ntiles; ++i) {
    const bool fine = grid.fine[static_cast<std::size_t>(i)] != 0;
    const auto& earlier = reuse.empty() ? std::nullopt : reuse[static_cast<std::size_t>(i)];
    if (!earlier || !reuseTile(*earlier, i % grid.tilesX, i / grid.tilesX, fine, tiles[static_cast<std::size_t>(i)]))
      todo.push_back(i);
  }
  const int ntodo = static_cast<int>(todo.size());
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  auto work = [&]() {
    for (;;) {
      const int k = next.fetch_add(1);
      if (k >= ntodo || failed.load()) return;
      const int i = todo[static_cast<std::size_t>(k)];
      TileOut& out = tiles[static_cast<std::size_t>(i)];
      try {
        out = buildTile(g, grid, st.resolution(i), s, i % grid.tilesX, i / grid.tilesX);
      } catch (const std::bad_alloc&) {
        out.error = "out of memory while building a tile: use a smaller tile_size or fewer jobs";
      }
      if (!out.error.empty()) failed.store(true);
    }
  };
  const int nthreads = std::max(1, std::min(jobs, ntodo));
  if (nthreads == 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(nthreads));
    for (int t = 0; t < nthreads; ++t) pool.emplace_back(work);
    for (auto& th : pool) th.join();
  }
  auto freeAll = [&]() {
    for (auto& t : tiles) {
      if (t.data) dtFree(t.data);
      t.data = nullptr;
    }
  };
  int totalPolys = 0;
  for (const auto& t : tiles) {
    if (!t.error.empty()) {
      const std::string err = t.error;
      freeAll();
      throw NavError("navmesh build failed: " + err);
    }
    if (t.polys > (1 << st.polyBits)) {
      freeAll();
      std::ostringstream msg;
      msg << "a " << (t.fine ? "fine " : "") << "tile has " << t.polys << " polygons, more than the "
          << (1 << st.polyBits) << " that fit in a polygon reference with " << ntiles
          << " tiles: decrease tile_size" << (t.fine ? " or fine_factor" : "");
      throw NavError(msg.str());
    }
    totalPolys += t.polys;
  }
  if (totalPolys == 0) {
    freeAll();
    throw NavError(noWalkableMessage(g, st.flatTriangles, st.walkableTypeTriangles, s));
  }
  if (built) {
    built->assign(static_cast<std::size_t>(ntiles), std::nullopt);
    for (int i : todo) {
      if (grid.tileStart[static_cast<std::size_t>(i)] == grid.tileStart[static_cast<std::size_t>(i) + 1]) continue;
      const TileOut& t = tiles[static_cast<std::size_t>(i)];
      (*built)[static_cast<std::size_t>(i)] =
          t.data ? std::string(reinterpret_cast<const char*>(t.data), static_cast<std::size_t>(t.size)) : std::string();
    }
  }

  // Pack the tiles into one navmesh, in tile order.
  dtNavMesh* nav = dtAllocNavMesh();
  if (!nav) {
    freeAll();
    throw std::bad_alloc();
  }
  dtNavMeshParams params;
  std::memset(&params, 0, sizeof(params));
  rcVcopy(params.orig, g.bmin);
  params.tileWidth = grid.tileW;
  params.tileHeight = grid.tileH;
  params.maxTiles = 1 << st.tileBits;
  params.maxPolys = 1 << st.polyBits;
  if (dtStatusFailed(nav->init(&params))) {
    freeAll();
    dtFreeNavMesh(nav);
    throw NavError("navmesh build failed: Detour rejected the navmesh parameters");
  }
  for (auto& t : tiles) {
    if (!t.data) continue;
    const dtStatus status = nav->addTile(t.data, t.size, DT_TILE_FREE_DATA, 0, nullptr);
    if (dtStatusFailed(status)) {
      freeAll();
      dtFreeNavMesh(nav);
      throw NavError("navmesh build failed: Detour rejected a tile");
    }
    t.data = nullptr;  // owned by the navmesh now
  }
  return new NavMesh(nav);
}

NavMesh* buildNavMesh(const InputMesh& mesh, const BuildConfig& cfg, int jobs) {
  TiledBuild build(mesh, cfg);
  return build.build(jobs, {}, nullptr);
}

}  // namespace navverse

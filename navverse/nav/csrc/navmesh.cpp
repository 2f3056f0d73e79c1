// Queries, indexing (islands, areas, sampling tables) and serialization of a Detour navmesh.
#include <DetourAlloc.h>
#include <DetourCommon.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>

#include "navmesh.h"

namespace navverse {
namespace {

constexpr int kMaxNodes = 65535;        // Detour's node pool limit (16-bit node indices)
constexpr int kMaxPathPolys = 65536;    // polygons in one corridor
constexpr int kMaxCirclePolys = 16384;  // polygons considered around a sampling center
constexpr int kMaxRayPolys = 2048;      // polygons one shortcut ray may cross
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr unsigned short kWalkFlag = 1;
constexpr unsigned short kExcludedFlag = 2;
constexpr unsigned short kFlatFlag = 4;  // the polygon's detail mesh is level: no height samples needed

constexpr char kBlobMagic[4] = {'N', 'V', 'D', 'T'};
constexpr std::uint32_t kBlobVersion = 1;

Vec3 nanVec() { return {kNaN, kNaN, kNaN}; }

Vec3 toWorld(const float* r) {
  Vec3 w;
  fromRecast(r, w.data());
  return w;
}

bool finite3(const Vec3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

double dist3(const float* a, const float* b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

double triArea(const float* a, const float* b, const float* c) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}

// Vertex `k` of detail triangle `t` of polygon `ip` (the detail mesh refers both to the polygon's
// own vertices and to extra detail vertices).
const float* detailVertex(const dtMeshTile* tile, int ip, const unsigned char* t, int k) {
  const dtPoly& poly = tile->polys[ip];
  const dtPolyDetail& pd = tile->detailMeshes[ip];
  if (t[k] < poly.vertCount) return &tile->verts[3 * poly.verts[t[k]]];
  return &tile->detailVerts[3 * (pd.vertBase + (t[k] - poly.vertCount))];
}

const unsigned char* detailTri(const dtMeshTile* tile, int ip, int k) {
  return &tile->detailTris[4 * (tile->detailMeshes[ip].triBase + static_cast<unsigned int>(k))];
}

// Calls fn(tile, tileIndex, polyIndex) for every ground polygon (not off-mesh connections) of every
// loaded tile, in tile order.
template <class Fn>
void forEachGroundPoly(const dtNavMesh* nav, Fn&& fn) {
  for (int i = 0; i < nav->getMaxTiles(); ++i) {
    const dtMeshTile* tile = nav->getTile(i);
    if (!tile || !tile->header) continue;
    for (int j = 0; j < tile->header->polyCount; ++j)
      if (tile->polys[j].getType() == DT_POLYTYPE_GROUND) fn(tile, i, j);
  }
}

// Uniform point in a triangle from two uniforms.
void pointInTriangle(const float* a, const float* b, const float* c, double u, double v, float* out) {
  const double su = std::sqrt(u);
  const double wa = 1.0 - su, wb = su * (1.0 - v), wc = su * v;
  for (int i = 0; i < 3; ++i) out[i] = static_cast<float>(wa * a[i] + wb * b[i] + wc * c[i]);
}

// Deterministic uniform doubles in [0, 1) from a 64-bit Mersenne twister (the same on every platform).
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : gen_(seed) {}
  double operator()() { return static_cast<double>(gen_() >> 11) * 0x1.0p-53; }

 private:
  std::mt19937_64 gen_;
};

// Bytes a tile's data must have, from the counts in its header (Detour's packed layout).
long long expectedTileSize(const dtMeshHeader& h) {
  auto a4 = [](long long x) { return (x + 3) & ~3LL; };
  return a4(sizeof(dtMeshHeader)) + a4(12LL * h.vertCount) + a4(static_cast<long long>(sizeof(dtPoly)) * h.polyCount) +
         a4(static_cast<long long>(sizeof(dtLink)) * h.maxLinkCount) +
         a4(static_cast<long long>(sizeof(dtPolyDetail)) * h.detailMeshCount) + a4(12LL * h.detailVertCount) +
         a4(4LL * h.detailTriCount) + a4(static_cast<long long>(sizeof(dtBVNode)) * h.bvNodeCount) +
         a4(static_cast<long long>(sizeof(dtOffMeshConnection)) * h.offMeshConCount);
}

class Writer {
 public:
  template <class T>
  void put(const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  std::string out;
};

class Reader {
 public:
  explicit Reader(const std::string& s) : s_(s) {}
  template <class T>
  T get() {
    T v;
    need(sizeof(T));
    std::memcpy(&v, s_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  const char* take(std::size_t n) {
    need(n);
    const char* p = s_.data() + pos_;
    pos_ += n;
    return p;
  }
  bool done() const { return pos_ == s_.size(); }

 private:
  void need(std::size_t n) const {
    if (s_.size() - pos_ < n) throw NavError("navmesh data is truncated");
  }
  const std::string& s_;
  std::size_t pos_ = 0;
};

}  // namespace

NavMesh::NavMesh(dtNavMesh* mesh) : nav_(mesh), excluded_(DT_MAX_AREAS, false) {
  query_ = dtAllocNavMeshQuery();
  if (!query_ || dtStatusFailed(query_->init(nav_, kMaxNodes))) {
    dtFreeNavMeshQuery(query_);
    dtFreeNavMesh(nav_);
    throw std::bad_alloc();
  }
  allFilter_.setIncludeFlags(0xffff);
  allFilter_.setExcludeFlags(0);
  pathFilter_.setIncludeFlags(kWalkFlag);
  pathFilter_.setExcludeFlags(kExcludedFlag);
  for (int i = 0; i < DT_MAX_AREAS; ++i) {
    allFilter_.setAreaCost(i, 1.0f);
    pathFilter_.setAreaCost(i, 1.0f);
  }
  polyBuf_.resize(kMaxPathPolys);
  index();
  resetFlags();
}

NavMesh::~NavMesh() {
  dtFreeNavMeshQuery(query_);
  dtFreeNavMesh(nav_);
}

// ---------------------------------------------------------------- indexing

void NavMesh::index() {
  const dtNavMesh* nav = nav_;
  const int maxTiles = nav->getMaxTiles();
  tileBase_.assign(static_cast<std::size_t>(maxTiles), 0);
  numTiles_ = 0;
  numPolys_ = 0;
  for (int i = 0; i < maxTiles; ++i) {
    const dtMeshTile* tile = nav->getTile(i);
    tileBase_[static_cast<std::size_t>(i)] = numPolys_;
    if (!tile || !tile->header) continue;
    ++numTiles_;
    numPolys_ += tile->header->polyCount;
    climb_ = std::max(climb_, tile->header->walkableClimb);
  }

  // Bounds of every vertex (polygon and detail), in the Recast frame.
  bool any = false;
  for (int i = 0; i < maxTiles; ++i) {
    const dtMeshTile* tile = nav->getTile(i);
    if (!tile || !tile->header) continue;
    auto grow = [&](const float* v) {
      if (!any) {
        dtVcopy(bmin_, v);
        dtVcopy(bmax_, v);
        any = true;
      }
      dtVmin(bmin_, v);
      dtVmax(bmax_, v);
    };
    for (int k = 0; k < tile->header->vertCount; ++k) grow(&tile->verts[3 * k]);
    for (int k = 0; k < tile->header->detailVertCount; ++k) grow(&tile->detailVerts[3 * k]);
  }

  // Islands: connected components over polygon links (within and across tiles).
  polyIsland_.assign(static_cast<std::size_t>(numPolys_), -1);
  std::vector<double> areas;
  std::vector<std::pair<int, int>> stack;  // (tile index, polygon index)
  for (int i = 0; i < maxTiles; ++i) {
    const dtMeshTile* tile = nav->getTile(i);
    if (!tile || !tile->header) continue;
    for (int j = 0; j < tile->header->polyCount; ++j) {
      const std::size_t flat = static_cast<std::size_t>(tileBase_[static_cast<std::size_t>(i)] + j);
      if (polyIsland_[flat] >= 0) continue;
      const int island = static_cast<int>(areas.size());
      areas.push_back(0.0);
      polyIsland_[flat] = island;
      stack.assign(1, {i, j});
      while (!stack.empty()) {
        const auto [ti, pi] = stack.back();
        stack.pop_back();
        const dtMeshTile* t = nav->getTile(ti);
        const dtPoly& poly = t->polys[pi];
        if (poly.getType() == DT_POLYTYPE_GROUND) areas[static_cast<std::size_t>(island)] += polyArea(t, pi);
        for (unsigned int k = poly.firstLink; k != DT_NULL_LINK; k = t->links[k].next) {
          const dtPolyRef nref = t->links[k].ref;
          if (!nref) continue;
          const int nti = static_cast<int>(nav->decodePolyIdTile(nref));
          const int npi = static_cast<int>(nav->decodePolyIdPoly(nref));
          const std::size_t nflat = static_cast<std::size_t>(tileBase_[static_cast<std::size_t>(nti)] + npi);
          if (polyIsland_[nflat] >= 0) continue;
          polyIsland_[nflat] = island;
          stack.emplace_back(nti, npi);
        }
      }
    }
  }

  // Number islands by decreasing area (island 0 is the largest); ties keep discovery order.
  std::vector<int> order(areas.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return areas[a] > areas[b]; });
  std::vector<int> rank(areas.size());
  islandArea_.assign(areas.size(), 0.0);
  for (std::size_t r = 0; r < order.size(); ++r) {
    rank[static_cast<std::size_t>(order[r])] = static_cast<int>(r);
    islandArea_[r] = areas[static_cast<std::size_t>(order[r])];
  }
  for (int& isl : polyIsland_) isl = rank[static_cast<std::size_t>(isl)];

  // Detail triangles grouped by island, with cumulative areas for sampling.
  std::vector<std::size_t> counts(islandArea_.size() + 1, 0);
  forEachGroundPoly(nav, [&](const dtMeshTile* tile, int i, int j) {
    const int isl = polyIsland_[static_cast<std::size_t>(tileBase_[static_cast<std::size_t>(i)] + j)];
    counts[static_cast<std::size_t>(isl) + 1] += tile->detailMeshes[j].triCount;
  });
  for (std::size_t k = 1; k < counts.size(); ++k) counts[k] += counts[k - 1];
  islandTri_ = counts;
  tris_.assign(counts.back(), TriRef{0, 0});
  std::vector<double> triArea_(counts.back(), 0.0);
  std::vector<std::size_t> fill(counts.begin(), counts.end() - 1);
  forEachGroundPoly(nav, [&](const dtMeshTile* tile, int i, int j) {
    const dtPolyRef base = nav->getPolyRefBase(tile);
    const int isl = polyIsland_[static_cast<std::size_t>(tileBase_[static_cast<std::size_t>(i)] + j)];
    for (int k = 0; k < tile->detailMeshes[j].triCount; ++k) {
      const unsigned char* t = detailTri(tile, j, k);
      const std::size_t slot = fill[static_cast<std::size_t>(isl)]++;
      tris_[slot] = TriRef{base | static_cast<dtPolyRef>(j), k};
      triArea_[slot] = triArea(detailVertex(tile, j, t, 0), detailVertex(tile, j, t, 1), detailVertex(tile, j, t, 2));
    }
  });
  triCum_.resize(triArea_.size());
  std::partial_sum(triArea_.begin(), triArea_.end(), triCum_.begin());
  totalArea_ = triCum_.empty() ? 0.0 : triCum_.back();
  polyanya_.build(nav_, tileBase_);
  // Level polygons: every corner and detail vertex at one height (to a micrometre).
  polyLevel_.assign(static_cast<std::size_t>(numPolys_), false);
  forEachGroundPoly(nav, [&](const dtMeshTile* tile, int i, int j) {
    float lo = FLT_MAX, hi = -FLT_MAX;
    for (int k = 0; k < tile->detailMeshes[j].triCount; ++k) {
      const unsigned char* t = detailTri(tile, j, k);
      for (int v = 0; v < 3; ++v) {
        const float y = detailVertex(tile, j, t, v)[1];
        lo = std::min(lo, y);
        hi = std::max(hi, y);
      }
    }
    polyLevel_[static_cast<std::size_t>(tileBase_[static_cast<std::size_t>(i)] + j)] = hi - lo <= 1e-6f;
  });
}

double NavMesh::polyArea(const dtMeshTile* tile, int ip) const {
  double area = 0.0;
  for (int k = 0; k < tile->detailMeshes[ip].triCount; ++k) {
    const unsigned char* t = detailTri(tile, ip, k);
    area += triArea(detailVertex(tile, ip, t, 0), detailVertex(tile, ip, t, 1), detailVertex(tile, ip, t, 2));
  }
  return area;
}

bool NavMesh::sampleInPoly(const dtMeshTile* tile, int ip, double u, double v, double w, float* out) const {
  const int ntri = tile->detailMeshes[ip].triCount;
  if (ntri == 0) return false;
  double total = polyArea(tile, ip);
  double target = u * total;
  for (int k = 0; k < ntri; ++k) {
    const unsigned char* t = detailTri(tile, ip, k);
    const float* a = detailVertex(tile, ip, t, 0);
    const float* b = detailVertex(tile, ip, t, 1);
    const float* c = detailVertex(tile, ip, t, 2);
    const double area = triArea(a, b, c);
    if (target < area || k == ntri - 1) {
      pointInTriangle(a, b, c, v, w, out);
      return true;
    }
    target -= area;
  }
  return false;
}

int NavMesh::islandOfRef(dtPolyRef ref) const {
  if (!ref || !nav_->isValidPolyRef(ref)) return -1;
  const unsigned int ti = nav_->decodePolyIdTile(ref);
  const unsigned int pi = nav_->decodePolyIdPoly(ref);
  return polyIsland_[static_cast<std::size_t>(tileBase_[ti]) + pi];
}

void NavMesh::resetFlags() {
  for (int i = 0; i < nav_->getMaxTiles(); ++i) {
    const dtMeshTile* tile = static_cast<const dtNavMesh*>(nav_)->getTile(i);
    if (!tile || !tile->header) continue;
    const dtPolyRef base = nav_->getPolyRefBase(tile);
    for (int j = 0; j < tile->header->polyCount; ++j) {
      const unsigned char area = tile->polys[j].getArea();
      const bool level = polyLevel_[static_cast<std::size_t>(tileBase_[static_cast<std::size_t>(i)] + j)];
      const unsigned short flags =
          kWalkFlag | (excluded_[area] ? kExcludedFlag : 0) | (level ? kFlatFlag : 0);
      nav_->setPolyFlags(base | static_cast<dtPolyRef>(j), flags);
    }
  }
}

// ---------------------------------------------------------------- filter

void NavMesh::setAreaCosts(const std::vector<double>& costs) {
  for (int i = 0; i < DT_MAX_AREAS && i < static_cast<int>(costs.size()); ++i)
    pathFilter_.setAreaCost(i, static_cast<float>(costs[static_cast<std::size_t>(i)]));
  updateUniform();
}

void NavMesh::updateUniform() {
  uniformCosts_ = true;
  for (int i = 0; i < DT_MAX_AREAS; ++i)
    if (pathFilter_.getAreaCost(i) != 1.0f || excluded_[static_cast<std::size_t>(i)]) uniformCosts_ = false;
}

void NavMesh::setLengthSampling(double step, double tolerance) {
  if (step > 0) sampling_.step = step;
  if (tolerance >= 0) sampling_.tolerance = tolerance;
}

void NavMesh::setExcludedAreas(const std::vector<int>& areas) {
  excluded_.assign(DT_MAX_AREAS, false);
  for (int a : areas)
    if (a >= 0 && a < DT_MAX_AREAS) excluded_[static_cast<std::size_t>(a)] = true;
  updateUniform();
  resetFlags();
}

// ---------------------------------------------------------------- point queries

bool NavMesh::snap(const Vec3& p, double hext, double vext, bool pathFilter, dtPolyRef* ref, float* rc) const {
  *ref = 0;
  if (!finite3(p) || !(hext > 0) || !(vext > 0)) return false;
  float c[3];
  toRecast(p.data(), c);
  const float ext[3] = {static_cast<float>(hext), static_cast<float>(vext), static_cast<float>(hext)};
  const dtStatus st = query_->findNearestPoly(c, ext, pathFilter ? &pathFilter_ : &allFilter_, ref, rc);
  return dtStatusSucceed(st) && *ref != 0;
}

bool NavMesh::isNavigable(const Vec3& p, double maxDz) const {
  if (!finite3(p) || !(maxDz >= 0)) return false;
  float c[3], rc[3];
  toRecast(p.data(), c);
  const float ext[3] = {1e-3f, static_cast<float>(std::max(maxDz, 1e-3)), 1e-3f};
  dtPolyRef ref = 0;
  bool over = false;
  const dtStatus st = query_->findNearestPoly(c, ext, &allFilter_, &ref, rc, &over);
  return dtStatusSucceed(st) && ref != 0 && over && std::abs(static_cast<double>(rc[1]) - c[1]) <= maxDz;
}

int NavMesh::islandOf(const Vec3& p, double hext, double vext) const {
  dtPolyRef ref;
  float rc[3];
  if (!snap(p, hext, vext, false, &ref, rc)) return -1;
  return islandOfRef(ref);
}

double NavMesh::distanceToWall(const Vec3& p, double radius, double hext, double vext) const {
  dtPolyRef ref;
  float rc[3];
  if (!(radius > 0) || !snap(p, hext, vext, false, &ref, rc)) return kNaN;
  float dist = 0, hitPos[3], hitNormal[3];
  const dtStatus st =
      query_->findDistanceToWall(ref, rc, static_cast<float>(radius), &allFilter_, &dist, hitPos, hitNormal);
  if (dtStatusFailed(st)) return kNaN;
  return dist;
}

// ---------------------------------------------------------------- paths

namespace {

// Length of a height profile (t = horizontal distance, y = height) after dropping the points that
// lie within `tol` of the chord between the kept ones (Douglas-Peucker on the vertical deviation).
double profileLength(const std::vector<double>& t, const std::vector<double>& y, double tol) {
  const std::size_t n = t.size();
  if (n < 2) return 0.0;
  std::vector<bool> keep(n, false);
  keep.front() = keep.back() = true;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [lo, hi] = stack.back();
    stack.pop_back();
    if (hi <= lo + 1) continue;
    double worst = tol;
    std::size_t at = 0;
    const double span = t[hi] - t[lo];
    for (std::size_t i = lo + 1; i < hi; ++i) {
      const double f = span > 0 ? (t[i] - t[lo]) / span : 0.0;
      const double dev = std::abs(y[i] - (y[lo] + f * (y[hi] - y[lo])));
      if (dev > worst) {
        worst = dev;
        at = i;
      }
    }
    if (at) {
      keep[at] = true;
      stack.push_back({lo, at});
      stack.push_back({at, hi});
    }
  }
  double len = 0.0;
  std::size_t prev = 0;
  for (std::size_t i = 1; i < n; ++i) {
    if (!keep[i]) continue;
    len += std::hypot(t[i] - t[prev], y[i] - y[prev]);
    prev = i;
  }
  return len;
}

// A polygon corridor and the string-pulled path through it.
struct Straight {
  std::vector<float> pts;  // Recast frame, 3 per point
  std::vector<dtPolyRef> refs;  // the polygon entered at each point (0 at the end)
  int count = 0;
};

bool straighten(const dtNavMeshQuery* query, const std::vector<dtPolyRef>& corridor, const float* s, const float* e,
                int options, Straight* out) {
  const int cap = 2 * static_cast<int>(corridor.size()) + 4;
  out->pts.assign(3 * static_cast<std::size_t>(cap), 0.0f);
  out->refs.assign(static_cast<std::size_t>(cap), 0);
  std::vector<unsigned char> flags(static_cast<std::size_t>(cap));
  const dtStatus st = query->findStraightPath(s, e, corridor.data(), static_cast<int>(corridor.size()),
                                              out->pts.data(), flags.data(), out->refs.data(), &out->count, cap,
                                              options);
  return dtStatusSucceed(st) && out->count > 0 && !dtStatusDetail(st, DT_BUFFER_TOO_SMALL);
}

// Detour's A* from sRef to eRef (area costs respected). Empty when the end is not reached
// (disconnected, excluded areas, or out of search nodes). Detour's any-angle option is not used:
// it ignores area costs.
std::vector<dtPolyRef> searchCorridor(const dtNavMeshQuery* query, const dtQueryFilter* filter,
                                      std::vector<dtPolyRef>& buf, dtPolyRef sRef, const float* s, dtPolyRef eRef,
                                      const float* e) {
  int n = 0;
  const dtStatus st = query->findPath(sRef, eRef, s, e, filter, buf.data(), &n, static_cast<int>(buf.size()));
  if (dtStatusFailed(st) || n == 0 || buf[static_cast<std::size_t>(n) - 1] != eRef || dtStatusDetail(st, DT_PARTIAL_RESULT))
    return {};
  return std::vector<dtPolyRef>(buf.begin(), buf.begin() + n);
}

// One pass of shortcuts over the corners of `path`: from each corner, the farthest later corner
// reachable in a straight line on the navmesh that costs no more than the path between them
// replaces the corners in between (Detour's A* scores polygon edge midpoints, so on large polygons
// its corridor can bend where nothing is in the way). Returns whether the corridor changed.
bool shortcutOnce(const dtNavMeshQuery* query, const dtQueryFilter* filter, const Straight& path,
                  std::vector<dtPolyRef>* corridor, float climb) {
  const int m = path.count;
  if (m < 3) return false;
  auto at = [&](int k) { return &path.pts[3 * static_cast<std::size_t>(k)]; };
  std::vector<dtPolyRef> visited(kMaxRayPolys);
  auto cast = [&](dtPolyRef from, const float* a, const float* b, dtRaycastHit* hit) {
    hit->path = visited.data();
    hit->maxPath = static_cast<int>(visited.size());
    hit->pathCount = 0;
    const dtStatus st = query->raycast(from, a, b, filter, DT_RAYCAST_USE_COSTS, hit);
    return dtStatusSucceed(st) && hit->t == FLT_MAX && hit->pathCount > 0 && !dtStatusDetail(st, DT_BUFFER_TOO_SMALL);
  };
  // The polygon each corner leaves from: the corridor's start polygon, then the polygon entered there.
  auto from = [&](int k) { return k == 0 ? corridor->front() : path.refs[static_cast<std::size_t>(k)]; };
  // Cost of each piece of the current path (a straight segment inside the corridor by construction).
  std::vector<double> cost(static_cast<std::size_t>(m - 1));
  for (int k = 0; k + 1 < m; ++k) {
    dtRaycastHit hit{};
    cost[static_cast<std::size_t>(k)] = cast(from(k), at(k), at(k + 1), &hit) ? hit.pathCost : kInf;
  }
  for (int i = 0; i + 2 < m; ++i) {
    double along = cost[static_cast<std::size_t>(i)];
    std::vector<double> prefix(static_cast<std::size_t>(m), kInf);
    for (int j = i + 1; j < m; ++j) {
      prefix[static_cast<std::size_t>(j)] = along;
      if (j + 1 < m) along += cost[static_cast<std::size_t>(j)];
    }
    for (int j = m - 1; j >= i + 2; --j) {
      dtRaycastHit hit{};
      if (!cast(from(i), at(i), at(j), &hit)) continue;
      if (!(hit.pathCost <= prefix[static_cast<std::size_t>(j)] * (1.0 + 1e-6))) continue;
      // The ray must end on the same surface as the corner (not on a level above or below it)...
      const dtPolyRef last = visited[static_cast<std::size_t>(hit.pathCount) - 1];
      float h = 0.0f;
      if (dtStatusFailed(query->getPolyHeight(last, at(j), &h)) || std::abs(h - at(j)[1]) > climb) continue;
      // ...and on a polygon of the corridor after corner i, where the rest of the corridor goes on.
      const auto first = std::find(corridor->begin(), corridor->end(), from(i));
      if (first == corridor->end()) continue;
      const auto rejoin = std::find(first, corridor->end(), last);
      if (rejoin == corridor->end()) continue;
      std::vector<dtPolyRef> spliced(corridor->begin(), first);
      spliced.insert(spliced.end(), visited.begin(), visited.begin() + hit.pathCount);
      spliced.insert(spliced.end(), rejoin + 1, corridor->end());
      *corridor = std::move(spliced);
      return true;
    }
  }
  return false;
}

// The path through `corridor` between two located points: string pulling (after shortcut passes,
// for corridors from Detour's A*), and its length along the surface.
PathResult corridorPath(const dtNavMeshQuery* query, const dtQueryFilter* filter, std::vector<dtPolyRef> corridor,
                        const LengthSampling& sampling, const float* s, const float* e, bool shortcuts, float climb) {
  PathResult res;
  res.length = kInf;
  Straight path;
  if (!straighten(query, corridor, s, e, 0, &path)) return res;
  for (int pass = 0; shortcuts && pass < 8 && shortcutOnce(query, filter, path, &corridor, climb); ++pass)
    if (!straighten(query, corridor, s, e, 0, &path)) return res;
  std::vector<Vec3> corners;
  for (int i = 0; i < path.count; ++i) corners.push_back(toWorld(&path.pts[3 * static_cast<std::size_t>(i)]));
  // Again with a point at every polygon edge crossing: the length is measured along it, so it
  // follows ramps and steps instead of cutting through them.
  Straight crossings;
  if (!straighten(query, corridor, s, e, DT_STRAIGHTPATH_ALL_CROSSINGS, &crossings)) return res;
  const std::vector<float>& pts = crossings.pts;
  const std::vector<dtPolyRef>& refs = crossings.refs;
  const int m = crossings.count;
  // Length: exact horizontally; vertically along the surface. Between crossings the path stays in
  // one polygon (refs[i]), which may bend (a ramp merged with the floor around it), so sample its
  // detail height every `sampling.step` meters, then simplify the height profile with a tolerance
  // above the voxel quantization (Douglas-Peucker), so flat floors measure flat and ramps and steps
  // add their rise.
  std::vector<double> t(1, 0.0), y(1, pts[1]);
  for (int i = 0; i + 1 < m; ++i) {
    const float* a = &pts[3 * static_cast<std::size_t>(i)];
    const float* b = &pts[3 * static_cast<std::size_t>(i + 1)];
    const double flat = std::hypot(b[0] - a[0], b[2] - a[2]);
    const dtPolyRef ref = refs[static_cast<std::size_t>(i)];
    unsigned short polyFlags = 0;
    const bool level = ref && dtStatusSucceed(query->getAttachedNavMesh()->getPolyFlags(ref, &polyFlags)) &&
                       (polyFlags & kFlatFlag);
    const int k = level ? 1 : std::max(1, std::min(4096, static_cast<int>(std::ceil(flat / sampling.step))));
    const double t0 = t.back();
    for (int j = 1; j <= k; ++j) {
      float p[3], q[3];
      dtVlerp(p, a, b, static_cast<float>(j) / static_cast<float>(k));
      if (j < k && ref && dtStatusSucceed(query->closestPointOnPoly(ref, p, q, nullptr))) p[1] = q[1];
      t.push_back(t0 + flat * j / k);
      y.push_back(p[1]);
    }
  }
  res.length = profileLength(t, y, sampling.tolerance);
  res.points = std::move(corners);
  return res;
}

}  // namespace

PathResult NavMesh::findPath(const Vec3& start, const Vec3& end, double hext, double vext) const {
  PathResult none;
  none.length = kInf;
  dtPolyRef sRef, eRef;
  float s[3], e[3];
  if (!snap(start, hext, vext, true, &sRef, s) || !snap(end, hext, vext, true, &eRef, e)) return none;
  PathResult res = shortestPath(sRef, s, eRef, e);
  if (std::isfinite(res.length)) res.end_index = 0;
  return res;
}

PathResult NavMesh::shortestPath(dtPolyRef sRef, const float* s, dtPolyRef eRef, const float* e) const {
  PathResult none;
  none.length = kInf;
  if (islandOfRef(sRef) != islandOfRef(eRef)) return none;
  std::vector<dtPolyRef> corridor;
  // The exact search when nothing is weighted or excluded. Within one island every point is
  // reachable then, so anything but a found corridor (the search gave up) falls back to Detour.
  if (uniformCosts_ && polyanya_.corridor(sRef, s, eRef, e, &corridor) == Polyanya::Outcome::kFound)
    return corridorPath(query_, &pathFilter_, std::move(corridor), sampling_, s, e, false, climb_);
  corridor = searchCorridor(query_, &pathFilter_, polyBuf_, sRef, s, eRef, e);
  if (corridor.empty()) return none;
  return corridorPath(query_, &pathFilter_, std::move(corridor), sampling_, s, e, true, climb_);
}

PathResult NavMesh::findPathMulti(const Vec3& start, const std::vector<Vec3>& ends, double hext, double vext) const {
  PathResult best;
  best.length = kInf;
  dtPolyRef sRef;
  float s[3];
  if (!snap(start, hext, vext, true, &sRef, s)) return best;
  struct Goal {
    double euclid;
    int index;
    dtPolyRef ref;
    float pos[3];
  };
  std::vector<Goal> goals;
  for (std::size_t i = 0; i < ends.size(); ++i) {
    Goal g{0.0, static_cast<int>(i), 0, {0, 0, 0}};
    if (!snap(ends[i], hext, vext, true, &g.ref, g.pos)) continue;
    g.euclid = dist3(s, g.pos);
    goals.push_back(g);
  }
  // The straight-line distance bounds the path length from below: visit goals nearest first and
  // stop once no remaining goal can beat the best path.
  std::stable_sort(goals.begin(), goals.end(), [](const Goal& a, const Goal& b) { return a.euclid < b.euclid; });
  for (const Goal& g : goals) {
    if (g.euclid >= best.length) break;
    PathResult r = shortestPath(sRef, s, g.ref, g.pos);
    if (r.length < best.length) {
      best = std::move(r);
      best.end_index = g.index;
    }
  }
  return best;
}

// ---------------------------------------------------------------- random points

Vec3 NavMesh::randomPoint(std::uint64_t seed, int island) const {
  std::size_t a = 0, b = tris_.size();
  if (island >= 0) {
    if (island >= numIslands()) return nanVec();
    a = islandTri_[static_cast<std::size_t>(island)];
    b = islandTri_[static_cast<std::size_t>(island) + 1];
  }
  if (a == b) return nanVec();
  const double lo = a > 0 ? triCum_[a - 1] : 0.0;
  const double hi = triCum_[b - 1];
  if (!(hi > lo)) return nanVec();
  Uniform rand(seed);
  const double target = lo + rand() * (hi - lo);
  std::size_t k = static_cast<std::size_t>(
      std::upper_bound(triCum_.begin() + static_cast<std::ptrdiff_t>(a), triCum_.begin() + static_cast<std::ptrdiff_t>(b), target) -
      triCum_.begin());
  k = std::min(k, b - 1);
  const dtMeshTile* tile = nullptr;
  const dtPoly* poly = nullptr;
  nav_->getTileAndPolyByRefUnsafe(tris_[k].poly, &tile, &poly);
  const int ip = static_cast<int>(poly - tile->polys);
  const unsigned char* t = detailTri(tile, ip, tris_[k].tri);
  float out[3];
  const double u = rand(), v = rand();
  pointInTriangle(detailVertex(tile, ip, t, 0), detailVertex(tile, ip, t, 1), detailVertex(tile, ip, t, 2), u, v, out);
  return toWorld(out);
}

Vec3 NavMesh::randomPointNear(const Vec3& center, double radius, std::uint64_t seed, int maxTries, double hext,
                              double vext) const {
  dtPolyRef cref;
  float c[3];
  if (!(radius > 0) || maxTries < 1 || !snap(center, hext, vext, false, &cref, c)) return nanVec();
  // Polygons connected to the center's polygon through edges that come within `radius` of it.
  std::vector<dtPolyRef> refs(kMaxCirclePolys);
  int n = 0;
  const dtStatus st = query_->findPolysAroundCircle(cref, c, static_cast<float>(radius), &allFilter_, refs.data(),
                                                    nullptr, nullptr, &n, kMaxCirclePolys);
  if (dtStatusFailed(st) || n == 0) return nanVec();
  std::vector<double> cum(static_cast<std::size_t>(n));
  std::vector<const dtMeshTile*> tiles(static_cast<std::size_t>(n));
  std::vector<int> polys(static_cast<std::size_t>(n));
  double total = 0.0;
  for (int i = 0; i < n; ++i) {
    const dtMeshTile* tile = nullptr;
    const dtPoly* poly = nullptr;
    nav_->getTileAndPolyByRefUnsafe(refs[static_cast<std::size_t>(i)], &tile, &poly);
    tiles[static_cast<std::size_t>(i)] = tile;
    polys[static_cast<std::size_t>(i)] = static_cast<int>(poly - tile->polys);
    if (poly->getType() == DT_POLYTYPE_GROUND) total += polyArea(tile, polys[static_cast<std::size_t>(i)]);
    cum[static_cast<std::size_t>(i)] = total;
  }
  if (!(total > 0)) return nanVec();
  Uniform rand(seed);
  for (int attempt = 0; attempt < maxTries; ++attempt) {
    const double target = rand() * total;
    std::size_t k = static_cast<std::size_t>(std::upper_bound(cum.begin(), cum.end(), target) - cum.begin());
    k = std::min(k, cum.size() - 1);
    float p[3];
    const double u = rand(), v = rand(), w = rand();
    if (!sampleInPoly(tiles[k], polys[k], u, v, w, p)) continue;
    if (dist3(p, c) <= radius) return toWorld(p);
  }
  return nanVec();
}

// ---------------------------------------------------------------- whole mesh

std::array<double, 6> NavMesh::bounds() const {
  const Vec3 lo = toWorld(bmin_), hi = toWorld(bmax_);
  return {std::min(lo[0], hi[0]), std::min(lo[1], hi[1]), std::min(lo[2], hi[2]),
          std::max(lo[0], hi[0]), std::max(lo[1], hi[1]), std::max(lo[2], hi[2])};
}

void NavMesh::polygons(std::vector<std::vector<Vec3>>* polys, std::vector<unsigned char>* areas) const {
  polys->clear();
  areas->clear();
  const dtNavMesh* nav = nav_;
  forEachGroundPoly(nav, [&](const dtMeshTile* tile, int /*tileIndex*/, int j) {
    const dtPoly& poly = tile->polys[j];
    std::vector<Vec3> ring;
    for (int k = 0; k < poly.vertCount; ++k) ring.push_back(toWorld(&tile->verts[3 * poly.verts[k]]));
    polys->push_back(std::move(ring));
    areas->push_back(poly.getArea());
  });
}

std::vector<std::array<Vec3, 2>> NavMesh::boundaryEdges() const {
  std::vector<std::array<Vec3, 2>> edges;
  const dtNavMesh* nav = nav_;
  forEachGroundPoly(nav, [&](const dtMeshTile* tile, int /*tileIndex*/, int j) {
    const dtPoly& poly = tile->polys[j];
    for (int k = 0; k < poly.vertCount; ++k) {
      bool open = poly.neis[k] == 0;
      if (poly.neis[k] & DT_EXT_LINK) {  // a tile border: open unless a link crosses this edge
        open = true;
        for (unsigned int l = poly.firstLink; l != DT_NULL_LINK; l = tile->links[l].next)
          if (tile->links[l].edge == k) {
            open = false;
            break;
          }
      }
      if (!open) continue;
      const int next = (k + 1) % poly.vertCount;
      edges.push_back({toWorld(&tile->verts[3 * poly.verts[k]]), toWorld(&tile->verts[3 * poly.verts[next]])});
    }
  });
  return edges;
}

TopDown NavMesh::topDown(double mpp, bool useHeight, double height, double eps) const {
  TopDown td;
  const std::array<double, 6> b = bounds();
  td.origin_x = b[0];
  td.origin_y = b[4];
  td.cols = std::max(1, static_cast<int>(std::ceil((b[3] - b[0]) / mpp - 1e-9)));
  td.rows = std::max(1, static_cast<int>(std::ceil((b[4] - b[1]) / mpp - 1e-9)));
  if (static_cast<double>(td.cols) * td.rows > 4e8) throw NavError("top-down view too large: increase meters_per_pixel");
  td.mask.assign(static_cast<std::size_t>(td.rows) * static_cast<std::size_t>(td.cols), 0);
  const dtNavMesh* nav = nav_;
  forEachGroundPoly(nav, [&](const dtMeshTile* tile, int /*tileIndex*/, int j) {
    for (int k = 0; k < tile->detailMeshes[j].triCount; ++k) {
      const unsigned char* t = detailTri(tile, j, k);
      Vec3 v[3];
      for (int m = 0; m < 3; ++m) v[m] = toWorld(detailVertex(tile, j, t, m));
      const double xmin = std::min({v[0][0], v[1][0], v[2][0]}), xmax = std::max({v[0][0], v[1][0], v[2][0]});
      const double ymin = std::min({v[0][1], v[1][1], v[2][1]}), ymax = std::max({v[0][1], v[1][1], v[2][1]});
      const int c0 = std::max(0, static_cast<int>(std::floor((xmin - td.origin_x) / mpp - 0.5)));
      const int c1 = std::min(td.cols - 1, static_cast<int>(std::ceil((xmax - td.origin_x) / mpp - 0.5)));
      const int r0 = std::max(0, static_cast<int>(std::floor((td.origin_y - ymax) / mpp - 0.5)));
      const int r1 = std::min(td.rows - 1, static_cast<int>(std::ceil((td.origin_y - ymin) / mpp - 0.5)));
      const double d = (v[1][1] - v[2][1]) * (v[0][0] - v[2][0]) + (v[2][0] - v[1][0]) * (v[0][1] - v[2][1]);
      if (std::abs(d) < 1e-12) continue;
      for (int r = r0; r <= r1; ++r) {
        const double y = td.origin_y - (r + 0.5) * mpp;
        for (int c = c0; c <= c1; ++c) {
          const double x = td.origin_x + (c + 0.5) * mpp;
          const double l0 = ((v[1][1] - v[2][1]) * (x - v[2][0]) + (v[2][0] - v[1][0]) * (y - v[2][1])) / d;
          const double l1 = ((v[2][1] - v[0][1]) * (x - v[2][0]) + (v[0][0] - v[2][0]) * (y - v[2][1])) / d;
          const double l2 = 1.0 - l0 - l1;
          if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9) continue;
          if (useHeight) {
            const double z = l0 * v[0][2] + l1 * v[1][2] + l2 * v[2][2];
            if (std::abs(z - height) > eps) continue;
          }
          td.mask[static_cast<std::size_t>(r) * static_cast<std::size_t>(td.cols) + static_cast<std::size_t>(c)] = 1;
        }
      }
    }
  });
  return td;
}

// ---------------------------------------------------------------- serialization

std::string NavMesh::toBytes() const {
  Writer w;
  w.out.append(kBlobMagic, 4);
  w.put<std::uint32_t>(kBlobVersion);
  w.put<std::int32_t>(DT_NAVMESH_VERSION);
  w.put<std::int32_t>(static_cast<std::int32_t>(sizeof(dtPolyRef)));
  const dtNavMeshParams* p = nav_->getParams();
  for (int i = 0; i < 3; ++i) w.put<float>(p->orig[i]);
  w.put<float>(p->tileWidth);
  w.put<float>(p->tileHeight);
  w.put<std::int32_t>(p->maxTiles);
  w.put<std::int32_t>(p->maxPolys);
  const dtNavMesh* nav = nav_;
  w.put<std::int32_t>(numTiles_);
  for (int i = 0; i < nav->getMaxTiles(); ++i) {
    const dtMeshTile* tile = nav->getTile(i);
    if (!tile || !tile->header || !tile->dataSize) continue;
    w.put<std::uint64_t>(static_cast<std::uint64_t>(nav->getTileRef(tile)));
    w.put<std::int32_t>(tile->dataSize);
    w.out.append(reinterpret_cast<const char*>(tile->data), static_cast<std::size_t>(tile->dataSize));
  }
  return w.out;
}

NavMesh* NavMesh::fromBytes(const std::string& blob) {
  Reader r(blob);
  const char* magic = r.take(4);
  if (std::memcmp(magic, kBlobMagic, 4) != 0) throw NavError("not navmesh tile data (bad magic)");
  const auto version = r.get<std::uint32_t>();
  if (version != kBlobVersion)
    throw NavError("navmesh tile data v" + std::to_string(version) + ", this build reads v" +
                   std::to_string(kBlobVersion) + ": rebuild the navmesh");
  const auto dtVersion = r.get<std::int32_t>();
  const auto refSize = r.get<std::int32_t>();
  if (dtVersion != DT_NAVMESH_VERSION || refSize != static_cast<std::int32_t>(sizeof(dtPolyRef)))
    throw NavError("navmesh tiles were written by Detour tile format v" + std::to_string(dtVersion) + " with " +
                   std::to_string(8 * refSize) + "-bit polygon references; this Detour reads v" +
                   std::to_string(DT_NAVMESH_VERSION) + " with " + std::to_string(8 * sizeof(dtPolyRef)) +
                   "-bit references: rebuild the navmesh");
  dtNavMeshParams params;
  std::memset(&params, 0, sizeof(params));
  for (int i = 0; i < 3; ++i) params.orig[i] = r.get<float>();
  params.tileWidth = r.get<float>();
  params.tileHeight = r.get<float>();
  params.maxTiles = r.get<std::int32_t>();
  params.maxPolys = r.get<std::int32_t>();
  const auto ntiles = r.get<std::int32_t>();
  if (params.maxTiles < 1 || params.maxTiles > (1 << 22) || params.maxPolys < 1 || ntiles < 0 ||
      ntiles > params.maxTiles || !(params.tileWidth > 0) || !(params.tileHeight > 0))
    throw NavError("navmesh data is corrupt (bad parameters)");
  dtNavMesh* nav = dtAllocNavMesh();
  if (!nav) throw std::bad_alloc();
  if (dtStatusFailed(nav->init(&params))) {
    dtFreeNavMesh(nav);
    throw NavError("navmesh data is corrupt (Detour rejected its parameters)");
  }
  try {
    for (int i = 0; i < ntiles; ++i) {
      const auto ref = static_cast<dtTileRef>(r.get<std::uint64_t>());
      const auto size = r.get<std::int32_t>();
      if (size < static_cast<std::int32_t>(sizeof(dtMeshHeader))) throw NavError("navmesh data is corrupt (tile size)");
      const char* src = r.take(static_cast<std::size_t>(size));
      dtMeshHeader header;
      std::memcpy(&header, src, sizeof(header));
      if (header.magic != DT_NAVMESH_MAGIC || header.version != DT_NAVMESH_VERSION || header.polyCount < 0 ||
          header.vertCount < 0 || header.maxLinkCount < 0 || header.detailMeshCount < 0 ||
          header.detailVertCount < 0 || header.detailTriCount < 0 || header.bvNodeCount < 0 ||
          header.offMeshConCount < 0 || expectedTileSize(header) != size)
        throw NavError("navmesh data is corrupt (tile " + std::to_string(i) + ")");
      auto* data = static_cast<unsigned char*>(dtAlloc(static_cast<std::size_t>(size), DT_ALLOC_PERM));
      if (!data) throw std::bad_alloc();
      std::memcpy(data, src, static_cast<std::size_t>(size));
      if (dtStatusFailed(nav->addTile(data, size, DT_TILE_FREE_DATA, ref, nullptr))) {
        dtFree(data);
        throw NavError("navmesh data is corrupt (Detour rejected tile " + std::to_string(i) + ")");
      }
    }
    if (!r.done()) throw NavError("navmesh data is corrupt (trailing bytes)");
  } catch (...) {
    dtFreeNavMesh(nav);
    throw;
  }
  return new NavMesh(nav);
}

}  // namespace navverse

// The Polyanya search over a Detour navmesh (see polyanya.h).
#include "polyanya.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>

namespace navverse {
namespace {

constexpr double kTouch = 1e-4;   // m: points closer than this are the same point
constexpr double kSide = 1e-9;    // |sine| below which three points count as collinear
constexpr double kCornerGrid = 1e-3;  // m: hash cell of obstacle corners
constexpr double kSame = 1e-7;        // m: path lengths closer than this are equal
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------- geometry

inline Point2 sub(Point2 a, Point2 b) { return {a.x - b.x, a.y - b.y}; }
inline double crossV(Point2 a, Point2 b) { return a.x * b.y - a.y * b.x; }
inline double dotV(Point2 a, Point2 b) { return a.x * b.x + a.y * b.y; }
inline double len(Point2 a) { return std::sqrt(a.x * a.x + a.y * a.y); }  // no overflow at map scales
inline Point2 lerp(Point2 a, Point2 b, double s) { return {a.x + (b.x - a.x) * s, a.y + (b.y - a.y) * s}; }

// Sine of the angle at `a` from `b` to `c`: > 0 when c is left of the ray a -> b.
inline double side(Point2 a, Point2 b, Point2 c) {
  const Point2 u = sub(b, a), w = sub(c, a);
  const double l2 = dotV(u, u) * dotV(w, w);
  return l2 > 0 ? crossV(u, w) / std::sqrt(l2) : 0.0;
}

inline bool same(Point2 a, Point2 b) { return len(sub(a, b)) < kTouch; }

// A lower bound of the path length from root r through the interval [lo, hi] to t: t is mirrored
// across the interval's line when it lies on r's side; the straight line if it passes through the
// interval, otherwise the bend at the nearer end.
double heuristic(Point2 r, Point2 lo, Point2 hi, Point2 t) {
  const Point2 d = sub(hi, lo);
  const double dd = dotV(d, d);
  if (dd <= 0) return len(sub(lo, r)) + len(sub(t, lo));
  const double sr = crossV(d, sub(r, lo)), st = crossV(d, sub(t, lo));
  if ((sr > 0 && st > 0) || (sr < 0 && st < 0)) {  // mirror t
    const double k = dotV(sub(t, lo), d) / dd;
    const Point2 foot = {lo.x + d.x * k, lo.y + d.y * k};
    t = {2 * foot.x - t.x, 2 * foot.y - t.y};
  }
  const double a = crossV(sub(t, r), sub(lo, r)), b = crossV(sub(t, r), sub(hi, r));
  if ((a <= 0 && b >= 0) || (a >= 0 && b <= 0)) return len(sub(t, r));
  return std::min(len(sub(lo, r)) + len(sub(t, lo)), len(sub(hi, r)) + len(sub(t, hi)));
}

std::int64_t gridKey(long long ix, long long iy) {
  return (static_cast<std::int64_t>(ix) << 32) ^ static_cast<std::int64_t>(static_cast<std::uint32_t>(iy));
}

}  // namespace

// ---------------------------------------------------------------- index

int Polyanya::flat(dtPolyRef ref) const {
  return tileBase_[nav_->decodePolyIdTile(ref)] + static_cast<int>(nav_->decodePolyIdPoly(ref));
}

int Polyanya::cornerId(const Point2& p) const {
  const long long ix = std::llround(p.x / kCornerGrid), iy = std::llround(p.y / kCornerGrid);
  for (long long dx = -1; dx <= 1; ++dx)
    for (long long dy = -1; dy <= 1; ++dy) {
      const auto it = cornerGrid_.find(gridKey(ix + dx, iy + dy));
      if (it == cornerGrid_.end()) continue;
      const Point2& c = corners_[static_cast<std::size_t>(it->second)];
      if (len(sub(c, p)) < 2 * kCornerGrid) return it->second;
    }
  return -1;
}

void Polyanya::build(const dtNavMesh* nav, const std::vector<int>& tileBase) {
  nav_ = nav;
  tileBase_ = tileBase;
  int total = 0;
  for (int i = 0; i < nav->getMaxTiles(); ++i) {
    const dtMeshTile* tile = nav->getTile(i);
    if (tile && tile->header) total = std::max(total, tileBase[static_cast<std::size_t>(i)] + tile->header->polyCount);
  }
  refs_.assign(static_cast<std::size_t>(total), 0);
  polys_.assign(static_cast<std::size_t>(total), Poly{});
  pieces_.clear();
  cornerGrid_.clear();
  corners_.clear();

  struct Span {
    double t0, t1;
    int neighbor;
  };
  for (int i = 0; i < nav->getMaxTiles(); ++i) {
    const dtMeshTile* tile = nav->getTile(i);
    if (!tile || !tile->header) continue;
    const dtPolyRef base = nav->getPolyRefBase(tile);
    for (int j = 0; j < tile->header->polyCount; ++j) {
      const dtPolyRef ref = base | static_cast<dtPolyRef>(j);
      const int f = tileBase[static_cast<std::size_t>(i)] + j;
      refs_[static_cast<std::size_t>(f)] = ref;
      const dtPoly& poly = tile->polys[j];
      if (poly.getType() != DT_POLYTYPE_GROUND) continue;
      const int nv = poly.vertCount;
      auto vert = [&](int k) {
        const float* v = &tile->verts[3 * poly.verts[k % nv]];
        return Point2{v[0], v[2]};
      };
      double area2 = 0;
      for (int k = 0; k < nv; ++k) area2 += crossV(vert(k), vert(k + 1));
      std::vector<Piece> own;
      for (int k = 0; k < nv; ++k) {
        const Point2 v0 = vert(k), v1 = vert(k + 1);
        const Point2 e = sub(v1, v0);
        const double el2 = dotV(e, e);
        if (el2 <= 0) continue;
        std::vector<Span> spans;
        for (unsigned int l = poly.firstLink; l != DT_NULL_LINK; l = tile->links[l].next) {
          const dtLink& link = tile->links[l];
          if (link.edge != k || !link.ref) continue;
          Span span{0.0, 1.0, flat(link.ref)};
          if (link.side != 0xff) {
            // A portal to another tile covers part of the edge: where the neighbour's edge that
            // links back overlaps this one (exact, unlike the link's 8-bit bmin/bmax).
            const dtMeshTile* nt = nullptr;
            const dtPoly* np = nullptr;
            nav->getTileAndPolyByRefUnsafe(link.ref, &nt, &np);
            double best = -1;
            for (unsigned int m = np->firstLink; m != DT_NULL_LINK; m = nt->links[m].next) {
              if (nt->links[m].ref != ref) continue;
              const int e2 = nt->links[m].edge;
              const float* w0 = &nt->verts[3 * np->verts[e2]];
              const float* w1 = &nt->verts[3 * np->verts[(e2 + 1) % np->vertCount]];
              double ta = dotV(sub(Point2{w0[0], w0[2]}, v0), e) / el2;
              double tb = dotV(sub(Point2{w1[0], w1[2]}, v0), e) / el2;
              if (ta > tb) std::swap(ta, tb);
              ta = std::clamp(ta, 0.0, 1.0);
              tb = std::clamp(tb, 0.0, 1.0);
              if (tb - ta > best) {
                best = tb - ta;
                span.t0 = ta;
                span.t1 = tb;
              }
            }
            if (best < 0) {
              span.t0 = link.bmin / 255.0;
              span.t1 = link.bmax / 255.0;
            }
          }
          spans.push_back(span);
        }
        std::sort(spans.begin(), spans.end(), [](const Span& a, const Span& b) { return a.t0 < b.t0; });
        const double tol = kTouch / std::sqrt(el2);
        double cur = 0.0;
        auto piece = [&](double t0, double t1, int nb) {
          Piece p;
          const Point2 a = t0 <= 0 ? v0 : lerp(v0, v1, t0), b = t1 >= 1 ? v1 : lerp(v0, v1, t1);
          p.a = a;
          p.b = b;
          p.neighbor = nb;
          own.push_back(p);
        };
        for (const Span& s : spans) {
          if (s.t1 <= cur + tol) continue;
          if (s.t0 > cur + tol) piece(cur, s.t0, -1);
          piece(std::max(s.t0, cur), s.t1, s.neighbor);
          cur = s.t1;
        }
        if (cur < 1.0 - tol) piece(cur, 1.0, -1);
        if (!own.empty()) own.back().b = v1;  // the edge ends exactly at its vertex
      }
      if (area2 < 0) {  // make the boundary counter-clockwise
        std::reverse(own.begin(), own.end());
        for (Piece& p : own) std::swap(p.a, p.b);
      }
      Poly& out = polys_[static_cast<std::size_t>(f)];
      out.first = static_cast<int>(pieces_.size());
      out.count = static_cast<int>(own.size());
      for (const Piece& p : own) out.portals += p.neighbor >= 0;
      pieces_.insert(pieces_.end(), own.begin(), own.end());
    }
  }
  // Obstacle corners: ends of wall pieces where the free space around the point spans more than a
  // half turn (a taut path bends only around such reflex corners; room corners, straight walls and
  // walls crossing a tile border never make it turn). The free angle is summed over every polygon
  // touching the point; where levels overlap the sums add up, which can only keep extra corners.
  std::unordered_map<std::int64_t, double> freeAngle;
  auto key = [](const Point2& p) { return gridKey(std::llround(p.x / kCornerGrid), std::llround(p.y / kCornerGrid)); };
  for (const Poly& poly : polys_) {
    for (int k = 0; k < poly.count; ++k) {
      const Piece& in = pieces_[static_cast<std::size_t>(poly.first + k)];
      const Piece& out = pieces_[static_cast<std::size_t>(poly.first + (k + 1) % poly.count)];
      const Point2 u = sub(in.b, in.a), w = sub(out.b, out.a);
      freeAngle[key(in.b)] += kPi - std::atan2(crossV(u, w), dotV(u, w));  // interior angle at in.b
    }
  }
  auto freeAround = [&](const Point2& p) {  // with the neighbouring hash cells (float rounding)
    const long long ix = std::llround(p.x / kCornerGrid), iy = std::llround(p.y / kCornerGrid);
    double sum = 0;
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy) {
        const auto it = freeAngle.find(gridKey(ix + dx, iy + dy));
        if (it != freeAngle.end()) sum += it->second;
      }
    return sum;
  };
  for (const Piece& p : pieces_) {
    if (p.neighbor >= 0) continue;
    for (const Point2& c : {p.a, p.b}) {
      if (cornerId(c) >= 0 || freeAround(c) <= kPi + 1e-6) continue;
      const int id = static_cast<int>(corners_.size());
      corners_.push_back(c);
      cornerGrid_[key(c)] = id;
    }
  }
  bestG_.assign(corners_.size(), kInf);
  bestStamp_.assign(corners_.size(), 0);
}

// ---------------------------------------------------------------- search

struct Polyanya::Search {
  Point2 target;
  int targetPoly = -1;
  std::vector<Root>& roots;
  std::vector<Node>& nodes;
  std::vector<std::pair<double, int>>& heap;  // min-heap on f
  std::vector<double>& bestG;                 // corner id -> shortest known path length to it...
  std::vector<std::uint32_t>& bestStamp;      // ...valid when its stamp is this query's
  std::uint32_t stamp;

  double best(int id) const {
    const auto i = static_cast<std::size_t>(id);
    return bestStamp[i] == stamp ? bestG[i] : kInf;
  }
  // A new root at corner `id` (at `p`, its canonical position) reached straight from root `prev`;
  // -1 if a shorter path to the corner is known. Equal paths give equal lengths to the bit, as
  // every polygon around a corner names the same canonical point.
  int addRoot(int id, const Point2& p, int prev) {
    const Root& from = roots[static_cast<std::size_t>(prev)];
    const double g = from.g + len(sub(p, from.p));
    const double known = best(id);
    if (g > known + kSame) return -1;
    if (g < known) {
      bestG[static_cast<std::size_t>(id)] = g;
      bestStamp[static_cast<std::size_t>(id)] = stamp;
    }
    roots.push_back(Root{p, id, prev, g});
    return static_cast<int>(roots.size()) - 1;
  }
  void push(const Node& n) {
    nodes.push_back(n);
    heap.emplace_back(n.f, static_cast<int>(nodes.size()) - 1);
    std::push_heap(heap.begin(), heap.end(), std::greater<>());
  }
  std::pair<double, int> pop() {
    std::pop_heap(heap.begin(), heap.end(), std::greater<>());
    const auto top = heap.back();
    heap.pop_back();
    return top;
  }
};

void Polyanya::expand(Search& search, int nodeIndex) const {
  const Node node = search.nodes[static_cast<std::size_t>(nodeIndex)];
  const Poly& poly = polys_[static_cast<std::size_t>(node.poly)];
  const int m = poly.count;
  if (m < 3) return;
  const Piece* pc = &pieces_[static_cast<std::size_t>(poly.first)];
  int rootIndex = node.root;
  Root root = search.roots[static_cast<std::size_t>(rootIndex)];
  Point2 r = root.p;
  Point2 lo = node.lo, hi = node.hi;
  const Point2 mid = lerp(lo, hi, 0.5);

  // The entry piece: the one bordering the polygon we came from, under the interval.
  int entry = -1;
  double bestGap = kInf;
  for (int k = 0; k < m; ++k) {
    if (pc[k].neighbor != node.from) continue;
    const Point2 a = pc[k].a, b = pc[k].b;
    const Point2 e = sub(b, a);
    const double s = std::clamp(dotV(sub(mid, a), e) / std::max(dotV(e, e), 1e-300), 0.0, 1.0);
    const double gap = len(sub(mid, lerp(a, b, s)));
    if (gap < bestGap) {
      bestGap = gap;
      entry = k;
    }
  }
  if (entry < 0) return;
  const Point2 S = pc[entry].a, E = pc[entry].b;
  const Point2 se = sub(E, S);
  if (dotV(sub(lo, S), se) > dotV(sub(hi, S), se)) std::swap(lo, hi);  // lo nearer S, hi nearer E
  bool atLo = same(r, lo), atHi = same(r, hi);
  if (atLo && atHi) return;
  if (!atLo && !atHi && side(S, E, r) > -kSide) {
    // The root is on the line of the entry piece (to float precision: tiles round shared borders
    // differently): the cone through the interval has no width, and the only way on runs along
    // the line to the interval's nearer end. Turn there if it is an obstacle corner.
    const bool loNearer = len(sub(lo, r)) < len(sub(hi, r));
    if (!(loNearer ? same(lo, S) : same(hi, E))) return;
    const int id = cornerId(loNearer ? S : E);
    rootIndex = id >= 0 ? search.addRoot(id, corners_[static_cast<std::size_t>(id)], rootIndex) : -1;
    if (rootIndex < 0) return;
    root = search.roots[static_cast<std::size_t>(rootIndex)];
    r = root.p;
    atLo = loNearer;
    atHi = !loNearer;
  }

  // The rest of the boundary, from E around to S: chain piece k (1..m-1) is pc[(entry + k) % m].
  auto chain = [&](int k) -> const Piece& { return pc[(entry + k) % m]; };
  // Where the ray from r through `through` leaves the polygon: the first chain position (k, s) from
  // which the boundary lies left of the ray.
  auto exitOf = [&](Point2 through) -> std::pair<int, double> {
    for (int k = 1; k < m; ++k) {
      const Point2 a = chain(k).a, b = chain(k).b;
      if (side(r, through, b) > kSide) {
        if (side(r, through, a) > kSide) return {k, 0.0};
        // The cross product, unlike the sine, is affine along the piece: interpolate it.
        const double oa = crossV(sub(through, r), sub(a, r)), ob = crossV(sub(through, r), sub(b, r));
        return {k, ob > oa ? std::clamp(oa / (oa - ob), 0.0, 1.0) : 0.0};
      }
    }
    return {m - 1, 1.0};
  };
  // The cone is taken through the interval widened by kTouch at both ends: neighbouring tiles
  // round a shared vertex differently (by ~1e-5 m), and adjacent cones must overlap, not leave a
  // sliver of directions between them that no node covers.
  const double width = len(sub(hi, lo));
  const Point2 u = width > 0 ? Point2{(hi.x - lo.x) / width, (hi.y - lo.y) / width} : Point2{0, 0};
  const Point2 wideLo{lo.x - u.x * kTouch, lo.y - u.y * kTouch}, wideHi{hi.x + u.x * kTouch, hi.y + u.y * kTouch};
  const std::pair<int, double> first{1, 0.0}, last{m - 1, 1.0};
  const std::pair<int, double> xHi = atHi ? first : exitOf(wideHi);
  const std::pair<int, double> xLo = atLo ? last : exitOf(wideLo);

  // The target, when it is in this polygon: straight from r if it is in the cone, else around an
  // end of the interval that is an obstacle corner.
  if (node.poly == search.targetPoly) {
    const Point2 t = search.target;
    const double oHi = atHi ? 1.0 : side(r, wideHi, t), oLo = atLo ? -1.0 : side(r, wideLo, t);
    int via = -1;
    double cost = kInf;
    if (oHi >= -kSide && oLo <= kSide) {
      via = rootIndex;
      cost = root.g + len(sub(t, r));
    } else {
      const bool hiSide = oHi < -kSide;
      const int id = same(hiSide ? hi : lo, hiSide ? E : S) ? cornerId(hiSide ? E : S) : -1;
      if (id >= 0) {
        const Point2 corner = corners_[static_cast<std::size_t>(id)];
        via = search.addRoot(id, corner, rootIndex);
        if (via >= 0) cost = search.roots[static_cast<std::size_t>(via)].g + len(sub(t, corner));
      }
    }
    if (via >= 0) search.push(Node{t, t, -1, node.poly, via, nodeIndex, cost});
  }

  // Successors on the portals of the chain range [from, to] seen from root `seenFrom`.
  auto successors = [&](std::pair<int, double> from, std::pair<int, double> to, int seenFrom) {
    if (to < from) return;
    const Root& rt = search.roots[static_cast<std::size_t>(seenFrom)];
    const Point2 rp = rt.p;
    for (int k = from.first; k <= to.first; ++k) {
      const Piece& q = chain(k);
      if (q.neighbor < 0) continue;
      const Poly& next = polys_[static_cast<std::size_t>(q.neighbor)];
      if (next.portals <= 1 && q.neighbor != search.targetPoly) continue;  // a dead end
      const double s0 = k == from.first ? from.second : 0.0, s1 = k == to.first ? to.second : 1.0;
      const Point2 a = q.a, b = q.b;
      if ((s1 - s0) * len(sub(b, a)) < 1e-7) continue;
      const Point2 pa = s0 <= 0 ? a : lerp(a, b, s0), pb = s1 >= 1 ? b : lerp(a, b, s1);
      const double f = rt.g + heuristic(rp, pa, pb, search.target);
      search.push(Node{pa, pb, q.neighbor, node.poly, seenFrom, nodeIndex, f});
    }
  };
  successors(xHi, xLo, rootIndex);  // observable from r
  // Not observable from r: reachable by turning around an end of the interval that is an obstacle corner.
  auto turnAt = [&](const Point2& corner) {
    const int id = cornerId(corner);
    return id >= 0 ? search.addRoot(id, corners_[static_cast<std::size_t>(id)], rootIndex) : -1;
  };
  if (!atHi && same(hi, E)) {
    const int nr = turnAt(E);
    if (nr >= 0) successors(first, xHi, nr);
  }
  if (!atLo && same(lo, S)) {
    const int nr = turnAt(S);
    if (nr >= 0) successors(xLo, last, nr);
  }
}

Polyanya::Outcome Polyanya::corridor(dtPolyRef sRef, const float* s, dtPolyRef tRef, const float* t,
                                     std::vector<dtPolyRef>* out) const {
  out->clear();
  const int sp = flat(sRef), tp = flat(tRef);
  if (sp == tp) {
    out->push_back(sRef);
    return Outcome::kFound;
  }
  // Nudge both points off their polygons' borders (a root on a portal has a degenerate cone).
  auto inside = [&](int p, const float* q) {
    const Poly& poly = polys_[static_cast<std::size_t>(p)];
    Point2 c{0, 0};
    for (int k = 0; k < poly.count; ++k) {
      c.x += pieces_[static_cast<std::size_t>(poly.first + k)].a.x / poly.count;
      c.y += pieces_[static_cast<std::size_t>(poly.first + k)].a.y / poly.count;
    }
    const Point2 x{q[0], q[2]};
    const double d = len(sub(c, x));
    return d > kTouch ? lerp(x, c, kTouch / d) : x;
  };
  roots_.clear();
  nodes_.clear();
  heap_.clear();
  if (++stamp_ == 0) {  // the stamps wrapped around: forget every old value
    std::fill(bestStamp_.begin(), bestStamp_.end(), 0);
    stamp_ = 1;
  }
  Search search{{}, -1, roots_, nodes_, heap_, bestG_, bestStamp_, stamp_};
  search.target = inside(tp, t);
  search.targetPoly = tp;
  const Point2 start = inside(sp, s);
  search.roots.push_back(Root{start, -1, -1, 0.0});
  search.nodes.push_back(Node{start, start, sp, -1, 0, -1, 0.0});
  const Poly& p0 = polys_[static_cast<std::size_t>(sp)];
  for (int k = 0; k < p0.count; ++k) {
    const Piece& q = pieces_[static_cast<std::size_t>(p0.first + k)];
    if (q.neighbor < 0) continue;
    const Point2 a = q.a, b = q.b;
    search.push(Node{q.a, q.b, q.neighbor, sp, 0, 0, heuristic(start, a, b, search.target)});
  }
  while (!search.heap.empty()) {
    const auto [f, index] = search.pop();
    const Node& node = search.nodes[static_cast<std::size_t>(index)];
    if (node.poly == -1) {  // the target: read the corridor back along the parents
      for (int n = node.parent; n >= 0; n = search.nodes[static_cast<std::size_t>(n)].parent)
        out->push_back(refs_[static_cast<std::size_t>(search.nodes[static_cast<std::size_t>(n)].poly)]);
      std::reverse(out->begin(), out->end());
      return Outcome::kFound;
    }
    const Root& rt = search.roots[static_cast<std::size_t>(node.root)];
    if (rt.corner >= 0 && search.best(rt.corner) < rt.g - kSame) continue;  // a shorter way to its root exists
    if (search.nodes.size() > kMaxNodes) return Outcome::kGaveUp;
    expand(search, index);
  }
  return Outcome::kUnreachable;
}

}  // namespace navverse

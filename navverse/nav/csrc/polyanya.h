// Exact Euclidean shortest paths on a Detour navmesh: the Polyanya search (Cui, Harabor and
// Grastien, "Compromise-free Pathfinding on a Navigation Mesh", IJCAI 2017), implemented here over
// Detour's tiles.
//
// Detour's own A* scores polygon edge midpoints, so its polygon corridor can go around the wrong
// side of an obstacle and its string-pulled path be several percent longer than the shortest one.
// Polyanya searches intervals of polygon edges seen from a root point (the start, or an obstacle
// corner the path turns at) and expands them by projecting the cone of visibility through the next
// polygon; its heuristic is admissible, so the first time the target is reached the path is
// optimal. Distances are horizontal (the navmesh projected on the ground plane), which is what
// shortest walking paths on floors with ramps are to first order; the caller measures the result
// along the surface.
//
// Coordinates here are Recast's horizontal plane (x, z), in doubles.
#pragma once

#include <DetourNavMesh.h>

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace navverse {

// A point of the horizontal plane.
struct Point2 {
  double x = 0, y = 0;
};

class Polyanya {
 public:
  enum class Outcome { kFound, kUnreachable, kGaveUp };

  // Index every ground polygon of `nav` (tileBase[i]: first flat polygon index of tile i).
  void build(const dtNavMesh* nav, const std::vector<int>& tileBase);

  // Sets `out` to the polygons the shortest path from `s` (in polygon sRef) to `t` (in tRef)
  // crosses, in order. kGaveUp when the search grew past kMaxNodes. Points are Recast-frame
  // (x, y, z); y is ignored.
  Outcome corridor(dtPolyRef sRef, const float* s, dtPolyRef tRef, const float* t, std::vector<dtPolyRef>* out) const;

  // Largest number of search nodes one query may create (a guard against pathological meshes).
  static constexpr std::size_t kMaxNodes = 4000000;

 private:
  // A straight piece of a polygon's boundary, counter-clockwise: a wall or a portal to a neighbour
  // (a polygon edge may be split into several pieces where it borders polygons of another tile).
  struct Piece {
    Point2 a, b;
    int neighbor = -1;  // flat polygon index, -1 for a wall
  };
  struct Poly {
    int first = 0;  // pieces_[first .. first + count)
    int count = 0;
    int portals = 0;
  };
  struct Root {
    Point2 p;
    int corner;  // corner id, -1 for the start
    int prev;    // previous root, -1 for the start
    double g;    // path length from the start to this root
  };
  struct Node {
    Point2 lo, hi;   // the interval, on the boundary between `from` and `poly`
    int poly;      // the polygon to expand into
    int from;      // the polygon the interval was reached from (-1 for the start)
    int root;      // index into the search's roots
    int parent;    // index of the parent node (-1 for the start)
    double f;
  };
  struct Search;

  int flat(dtPolyRef ref) const;
  int cornerId(const Point2& p) const;
  void expand(Search& search, int nodeIndex) const;

  const dtNavMesh* nav_ = nullptr;
  std::vector<int> tileBase_;
  std::vector<dtPolyRef> refs_;  // by flat index
  std::vector<Poly> polys_;      // by flat index
  std::vector<Piece> pieces_;
  // Obstacle corners (ends of wall pieces), hashed on a 1 mm grid.
  std::unordered_map<std::int64_t, int> cornerGrid_;
  std::vector<Point2> corners_;
  // Search buffers, kept between queries (so a Polyanya answers one query at a time).
  mutable std::vector<Root> roots_;
  mutable std::vector<Node> nodes_;
  mutable std::vector<std::pair<double, int>> heap_;
  mutable std::vector<double> bestG_;
  mutable std::vector<std::uint32_t> bestStamp_;
  mutable std::uint32_t stamp_ = 0;
};

}  // namespace navverse

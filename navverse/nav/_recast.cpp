// Python binding of navverse::NavMesh (navverse/nav/csrc). Points are z-up world coordinates;
// the Python layer (navverse.nav.pathfinder) validates arguments before they get here.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "csrc/navmesh.h"

namespace py = pybind11;
using navverse::NavMesh;
using navverse::Vec3;

namespace {

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;

Vec3 vec3(const Points& a) {
  if (a.ndim() != 1 || a.shape(0) != 3) throw py::value_error("expected a point of shape (3,)");
  return {a.at(0), a.at(1), a.at(2)};
}

std::vector<Vec3> rows(const Points& a) {
  if (a.ndim() != 2 || a.shape(1) != 3) throw py::value_error("expected points of shape (N, 3)");
  std::vector<Vec3> out(static_cast<std::size_t>(a.shape(0)));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) out[static_cast<std::size_t>(i)] = {r(i, 0), r(i, 1), r(i, 2)};
  return out;
}

py::array_t<double> pointArray(const std::vector<Vec3>& pts) {
  py::array_t<double> out({static_cast<py::ssize_t>(pts.size()), static_cast<py::ssize_t>(3)});
  auto w = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (int k = 0; k < 3; ++k) w(static_cast<py::ssize_t>(i), k) = pts[i][static_cast<std::size_t>(k)];
  return out;
}

navverse::BuildConfig buildConfig(const py::dict& d) {
  navverse::BuildConfig c;
  auto f = [&](const char* key) { return d[key].cast<double>(); };
  auto b = [&](const char* key) { return d[key].cast<bool>(); };
  c.cell_size = f("cell_size");
  c.cell_height = f("cell_height");
  c.agent_height = f("agent_height");
  c.agent_radius = f("agent_radius");
  c.agent_max_climb = f("agent_max_climb");
  c.agent_max_slope = f("agent_max_slope");
  c.region_min_size = f("region_min_size");
  c.region_merge_size = f("region_merge_size");
  c.edge_max_len = f("edge_max_len");
  c.edge_max_error = f("edge_max_error");
  c.verts_per_poly = d["verts_per_poly"].cast<int>();
  c.detail_sample_dist = f("detail_sample_dist");
  c.detail_sample_max_error = f("detail_sample_max_error");
  c.filter_low_hanging_obstacles = b("filter_low_hanging_obstacles");
  c.filter_ledge_spans = b("filter_ledge_spans");
  c.filter_walkable_low_height_spans = b("filter_walkable_low_height_spans");
  c.fill_solid_interiors = b("fill_solid_interiors");
  c.tile_size = d["tile_size"].cast<int>();
  c.fine_region = d["fine_region"].cast<std::optional<std::array<double, 4>>>();
  c.fine_factor = d["fine_factor"].cast<int>();
  return c;
}

navverse::InputMesh inputMesh(const Points& vertices, const py::array_t<std::int32_t, py::array::c_style | py::array::forcecast>& faces,
                              const py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>& areas) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3) throw py::value_error("vertices must have shape (N, 3)");
  if (faces.ndim() != 2 || faces.shape(1) != 3) throw py::value_error("faces must have shape (M, 3)");
  if (areas.ndim() != 1 || areas.shape(0) != faces.shape(0)) throw py::value_error("areas must have shape (M,)");
  navverse::InputMesh mesh;
  mesh.vertices.assign(vertices.data(), vertices.data() + vertices.size());
  mesh.triangles.assign(faces.data(), faces.data() + faces.size());
  mesh.areas.assign(areas.data(), areas.data() + areas.size());
  const int nverts = static_cast<int>(vertices.shape(0));
  for (int t : mesh.triangles)
    if (t < 0 || t >= nverts) throw py::value_error("face index out of range");
  return mesh;
}

using Faces = py::array_t<std::int32_t, py::array::c_style | py::array::forcecast>;
using Areas = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>;

std::unique_ptr<NavMesh> build(const Points& vertices, const Faces& faces, const Areas& areas, const py::dict& settings,
                               int jobs) {
  navverse::InputMesh mesh = inputMesh(vertices, faces, areas);
  const navverse::BuildConfig cfg = buildConfig(settings);
  NavMesh* nav = nullptr;
  {
    py::gil_scoped_release release;
    nav = navverse::buildNavMesh(mesh, cfg, jobs);
  }
  return std::unique_ptr<NavMesh>(nav);
}

std::unique_ptr<navverse::TiledBuild> prepareTiles(const Points& vertices, const Faces& faces, const Areas& areas,
                                                   const py::dict& settings) {
  navverse::InputMesh mesh = inputMesh(vertices, faces, areas);
  const navverse::BuildConfig cfg = buildConfig(settings);
  py::gil_scoped_release release;
  return std::make_unique<navverse::TiledBuild>(std::move(mesh), cfg);
}

// (navmesh, built): built holds per tile the bytes built now (b"" for an empty tile), None otherwise.
py::tuple buildTiles(navverse::TiledBuild& self, int jobs, const py::list& reuse) {
  std::vector<std::optional<std::string>> earlier;
  earlier.reserve(reuse.size());
  for (const py::handle item : reuse) {
    if (item.is_none()) {
      earlier.emplace_back(std::nullopt);
    } else {
      earlier.emplace_back(item.cast<py::bytes>().cast<std::string>());
    }
  }
  std::vector<std::optional<std::string>> built;
  NavMesh* nav = nullptr;
  {
    py::gil_scoped_release release;
    nav = self.build(jobs, earlier, &built);
  }
  std::unique_ptr<NavMesh> owned(nav);
  py::list out;
  for (const auto& data : built) {
    if (data) {
      out.append(py::bytes(*data));
    } else {
      out.append(py::none());
    }
  }
  return py::make_tuple(std::move(owned), out);
}

}  // namespace

PYBIND11_MODULE(_recast, m) {
  m.doc() = "RecastNavigation (Recast + Detour) navmesh build and queries; z-up world coordinates.";
  m.attr("MAX_AREAS") = DT_MAX_AREAS;
  m.attr("NULL_AREA") = 0;
  m.attr("WALKABLE_AREA") = 63;

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const navverse::NavError& e) {
      py::object cls = py::module_::import("navverse.nav.errors").attr("NavMeshError");
      PyErr_SetString(cls.ptr(), e.what());
    }
  });

  py::class_<navverse::TiledBuild>(m, "TiledBuild",
                                   "A navmesh build prepared tile by tile, so tiles of an earlier build can be reused.")
      .def(py::init(&prepareTiles), py::arg("vertices"), py::arg("faces"), py::arg("areas"), py::arg("settings"))
      .def_property_readonly("num_tiles", &navverse::TiledBuild::numTiles)
      .def(
          "tile_key", [](const navverse::TiledBuild& self, int tile) { return py::bytes(self.tileKey(tile)); },
          py::arg("tile"), "The bytes tile `tile`'s result depends on (b'' when no triangle reaches it).")
      .def("build", &buildTiles, py::arg("jobs"), py::arg("reuse"),
           "Build the tiles `reuse` does not supply (a list with one bytes or None per tile); returns (navmesh, built).");

  py::class_<NavMesh>(m, "NavMesh")
      .def_static("build", &build, py::arg("vertices"), py::arg("faces"), py::arg("areas"), py::arg("settings"),
                  py::arg("jobs"), "Build from a z-up triangle mesh; releases the GIL while building.")
      .def_static(
          "from_bytes", [](const py::bytes& b) { return std::unique_ptr<NavMesh>(NavMesh::fromBytes(std::string(b))); },
          py::arg("data"))
      .def("to_bytes", [](const NavMesh& self) { return py::bytes(self.toBytes()); })
      .def("set_area_costs", &NavMesh::setAreaCosts, py::arg("costs"))
      .def("set_excluded_areas", &NavMesh::setExcludedAreas, py::arg("areas"))
      .def("set_length_sampling", &NavMesh::setLengthSampling, py::arg("step"), py::arg("tolerance"))
      .def(
          "snap",
          [](const NavMesh& self, const Points& pts, double hext, double vext) {
            const std::vector<Vec3> in = rows(pts);
            std::vector<Vec3> out(in.size());
            for (std::size_t i = 0; i < in.size(); ++i) {
              dtPolyRef ref;
              float rc[3];
              if (self.snap(in[i], hext, vext, false, &ref, rc)) {
                navverse::fromRecast(rc, out[i].data());
              } else {
                out[i].fill(std::numeric_limits<double>::quiet_NaN());
              }
            }
            return pointArray(out);
          },
          py::arg("points"), py::arg("max_horizontal"), py::arg("max_vertical"))
      .def(
          "is_navigable",
          [](const NavMesh& self, const Points& pts, double maxDz) {
            const std::vector<Vec3> in = rows(pts);
            py::array_t<bool> out(static_cast<py::ssize_t>(in.size()));
            auto w = out.mutable_unchecked<1>();
            for (std::size_t i = 0; i < in.size(); ++i) w(static_cast<py::ssize_t>(i)) = self.isNavigable(in[i], maxDz);
            return out;
          },
          py::arg("points"), py::arg("max_dz"))
      .def(
          "island_of",
          [](const NavMesh& self, const Points& pts, double hext, double vext) {
            const std::vector<Vec3> in = rows(pts);
            py::array_t<std::int64_t> out(static_cast<py::ssize_t>(in.size()));
            auto w = out.mutable_unchecked<1>();
            for (std::size_t i = 0; i < in.size(); ++i) w(static_cast<py::ssize_t>(i)) = self.islandOf(in[i], hext, vext);
            return out;
          },
          py::arg("points"), py::arg("max_horizontal"), py::arg("max_vertical"))
      .def(
          "distance_to_wall",
          [](const NavMesh& self, const Points& pts, double radius, double hext, double vext) {
            const std::vector<Vec3> in = rows(pts);
            py::array_t<double> out(static_cast<py::ssize_t>(in.size()));
            auto w = out.mutable_unchecked<1>();
            for (std::size_t i = 0; i < in.size(); ++i)
              w(static_cast<py::ssize_t>(i)) = self.distanceToWall(in[i], radius, hext, vext);
            return out;
          },
          py::arg("points"), py::arg("max_search_radius"), py::arg("max_horizontal"), py::arg("max_vertical"))
      .def(
          "find_path",
          [](const NavMesh& self, const Points& start, const Points& end, double hext, double vext) {
            const navverse::PathResult r = self.findPath(vec3(start), vec3(end), hext, vext);
            return py::make_tuple(pointArray(r.points), r.length);
          },
          py::arg("start"), py::arg("end"), py::arg("max_horizontal"), py::arg("max_vertical"))
      .def(
          "find_path_multi",
          [](const NavMesh& self, const Points& start, const Points& ends, double hext, double vext) {
            const navverse::PathResult r = self.findPathMulti(vec3(start), rows(ends), hext, vext);
            return py::make_tuple(pointArray(r.points), r.length, r.end_index);
          },
          py::arg("start"), py::arg("ends"), py::arg("max_horizontal"), py::arg("max_vertical"))
      .def(
          "random_point",
          [](const NavMesh& self, std::uint64_t seed, int island) {
            return pointArray({self.randomPoint(seed, island)});
          },
          py::arg("seed"), py::arg("island"))
      .def(
          "random_point_near",
          [](const NavMesh& self, const Points& center, double radius, std::uint64_t seed, int maxTries, double hext,
             double vext) {
            return pointArray({self.randomPointNear(vec3(center), radius, seed, maxTries, hext, vext)});
          },
          py::arg("center"), py::arg("radius"), py::arg("seed"), py::arg("max_tries"), py::arg("max_horizontal"),
          py::arg("max_vertical"))
      .def_property_readonly("num_islands", &NavMesh::numIslands)
      .def_property_readonly("island_areas", &NavMesh::islandAreas)
      .def_property_readonly("navigable_area", &NavMesh::navigableArea)
      .def_property_readonly("num_tiles", &NavMesh::numTiles)
      .def_property_readonly("num_polygons", &NavMesh::numPolygons)
      .def_property_readonly("bounds",
                             [](const NavMesh& self) {
                               const auto b = self.bounds();
                               return pointArray({{b[0], b[1], b[2]}, {b[3], b[4], b[5]}});
                             })
      .def("polygons",
           [](const NavMesh& self) {
             std::vector<std::vector<Vec3>> polys;
             std::vector<unsigned char> areas;
             self.polygons(&polys, &areas);
             py::list out;
             for (const auto& p : polys) out.append(pointArray(p));
             py::array_t<std::uint8_t> a(static_cast<py::ssize_t>(areas.size()));
             if (!areas.empty()) std::memcpy(a.mutable_data(), areas.data(), areas.size());
             return py::make_tuple(out, a);
           })
      .def("boundary_edges",
           [](const NavMesh& self) {
             const auto edges = self.boundaryEdges();
             py::array_t<double> out({static_cast<py::ssize_t>(edges.size()), static_cast<py::ssize_t>(2),
                                      static_cast<py::ssize_t>(3)});
             auto w = out.mutable_unchecked<3>();
             for (std::size_t i = 0; i < edges.size(); ++i)
               for (int e = 0; e < 2; ++e)
                 for (int k = 0; k < 3; ++k)
                   w(static_cast<py::ssize_t>(i), e, k) = edges[i][static_cast<std::size_t>(e)][static_cast<std::size_t>(k)];
             return out;
           })
      .def(
          "topdown",
          [](const NavMesh& self, double mpp, bool useHeight, double height, double eps) {
            navverse::TopDown td;
            {
              py::gil_scoped_release release;
              td = self.topDown(mpp, useHeight, height, eps);
            }
            py::array_t<bool> img({static_cast<py::ssize_t>(td.rows), static_cast<py::ssize_t>(td.cols)});
            std::memcpy(img.mutable_data(), td.mask.data(), td.mask.size());
            return py::make_tuple(img, td.origin_x, td.origin_y);
          },
          py::arg("meters_per_pixel"), py::arg("use_height"), py::arg("height"), py::arg("eps"));
}

// Python binding of navverse::Crowd (navverse/dynamics/csrc/crowd.h). Points are z-up world
// coordinates. A separate extension from navverse.nav._recast, whose bytes key every navmesh and
// episode artifact: the crowd can change without rebuilding them.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "csrc/crowd.h"

namespace py = pybind11;
using navverse::Crowd;
using navverse::CrowdAgentSpec;
using navverse::Vec3;

namespace {

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;

Vec3 vec3(const Points& a) {
  if (a.size() != 3) throw navverse::NavError("expected a point (x, y, z)");
  const double* d = a.data();
  return {d[0], d[1], d[2]};
}

}  // namespace

PYBIND11_MODULE(_crowd, m) {
  m.doc() = "Agents walking a navmesh (DetourCrowd); see navverse.dynamics.crowd.";
  // Local: only errors thrown by this module's functions (navverse.nav._recast maps its own to NavMeshError).
  py::register_local_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const navverse::NavError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  py::class_<CrowdAgentSpec>(m, "CrowdAgentSpec")
      .def(py::init<>())
      .def_readwrite("radius", &CrowdAgentSpec::radius)
      .def_readwrite("height", &CrowdAgentSpec::height)
      .def_readwrite("max_speed", &CrowdAgentSpec::max_speed)
      .def_readwrite("max_acceleration", &CrowdAgentSpec::max_acceleration)
      .def_readwrite("separation_weight", &CrowdAgentSpec::separation_weight)
      .def_readwrite("collision_query_range", &CrowdAgentSpec::collision_query_range)
      .def_readwrite("path_optimization_range", &CrowdAgentSpec::path_optimization_range)
      .def_readwrite("filter", &CrowdAgentSpec::filter)
      .def_readwrite("avoidance_quality", &CrowdAgentSpec::avoidance_quality);

  py::class_<Crowd>(m, "Crowd")
      .def(py::init([](const py::bytes& navmesh, int maxAgents, double maxAgentRadius,
                       const std::vector<std::vector<int>>& excluded, const std::vector<std::vector<double>>& costs) {
             return std::make_unique<Crowd>(std::string(navmesh), maxAgents, maxAgentRadius, excluded, costs);
           }),
           py::arg("navmesh"), py::arg("max_agents"), py::arg("max_agent_radius"), py::arg("excluded"),
           py::arg("costs"))
      .def(
          "add_agent",
          [](Crowd& self, const Points& p, const CrowdAgentSpec& spec, double reach) {
            return self.addAgent(vec3(p), spec, reach);
          },
          py::arg("position"), py::arg("spec"), py::arg("reach"))
      .def("remove_agent", &Crowd::removeAgent, py::arg("agent"))
      .def(
          "set_target",
          [](Crowd& self, int agent, const Points& p, double reach) { return self.setTarget(agent, vec3(p), reach); },
          py::arg("agent"), py::arg("target"), py::arg("reach"))
      .def(
          "set_velocity", [](Crowd& self, int agent, const Points& v) { return self.setVelocity(agent, vec3(v)); },
          py::arg("agent"), py::arg("velocity"))
      .def(
          "place", [](Crowd& self, int agent, const Points& p, double reach) { return self.place(agent, vec3(p), reach); },
          py::arg("agent"), py::arg("position"), py::arg("reach"))
      .def("update", &Crowd::update, py::arg("dt"), py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("max_agents", &Crowd::maxAgents)
      .def("target_state", &Crowd::targetState, py::arg("agent"))
      .def("state", [](const Crowd& self) {
        const int n = self.maxAgents();
        py::array_t<double> pos({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(3)});
        py::array_t<double> vel({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(3)});
        py::array_t<bool> active(static_cast<py::ssize_t>(n));
        py::array_t<std::int16_t> area(static_cast<py::ssize_t>(n));
        auto p = pos.mutable_unchecked<2>();
        auto v = vel.mutable_unchecked<2>();
        auto a = active.mutable_unchecked<1>();
        auto r = area.mutable_unchecked<1>();
        for (int i = 0; i < n; ++i) {
          const bool on = self.active(i);
          const Vec3 x = on ? self.position(i) : Vec3{0.0, 0.0, 0.0};
          const Vec3 u = on ? self.velocity(i) : Vec3{0.0, 0.0, 0.0};
          for (int k = 0; k < 3; ++k) {
            p(i, k) = x[static_cast<std::size_t>(k)];
            v(i, k) = u[static_cast<std::size_t>(k)];
          }
          a(i) = on;
          r(i) = static_cast<std::int16_t>(on ? self.areaAt(i) : -1);
        }
        return py::make_tuple(pos, vel, active, area);
      });
}

// The leg forces of the Spot model (navverse/sim/spot.py) for one physics step, in native code.
//
// The arithmetic is the module's formulas, operation for operation in the order Python evaluates
// them, in IEEE double precision (the extension is compiled without contracting a * b + c into fused
// multiply-adds), so the forces are the same bits Python's floats give. The norm of the heading is
// Python's own math.hypot, called here, so it rounds as Python's does.

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace py = pybind11;

namespace {

double item(PyObject* tuple, Py_ssize_t i) {
  const double value = PyFloat_AsDouble(PyTuple_GET_ITEM(tuple, i));
  if (value == -1.0 && PyErr_Occurred()) throw py::error_already_set();
  return value;
}

PyObject* tuple_of(py::handle h, Py_ssize_t size, const char* what) {
  PyObject* o = h.ptr();
  if (!PyTuple_Check(o) || PyTuple_GET_SIZE(o) != size) {
    throw std::invalid_argument(std::string(what) + " must be a tuple of " + std::to_string(size));
  }
  return o;
}

struct LegParameters {
  std::array<std::array<double, 3>, 4> hips;  // hip offsets from the base origin, body frame
  double share, stiffness, damping, max_push, rest, min_length, reach, ray_start, ray_length, traction_max;
  double default_friction;
};

class LegModel {
 public:
  LegModel(const std::array<std::array<double, 3>, 4>& hips, double share, double stiffness, double damping,
           double max_push, double rest, double min_length, double reach, double ray_start, double ray_length,
           double traction_max, double default_friction)
      : p_{hips,  share, stiffness, damping,    max_push,     rest,
           min_length, reach, ray_start, ray_length, traction_max, default_friction},
        hypot_(py::module_::import("math").attr("hypot")) {}

  // (force x, y, z, torque x, y, z, push of legs 0..3): `state` as getBasePositionAndOrientation
  // gives it, `velocity` as getBaseVelocity, `command` (vx, vy, wz), `hits` as rayTestBatch,
  // `friction` the friction of each static body by id, `body` the trunk's id.
  py::tuple forces(py::handle state, py::handle velocity, py::handle command, py::handle hits,
                   py::handle friction, long body) const {
    PyObject* st = tuple_of(state, 2, "state");
    PyObject* pos = tuple_of(PyTuple_GET_ITEM(st, 0), 3, "position");
    PyObject* orn = tuple_of(PyTuple_GET_ITEM(st, 1), 4, "orientation");
    PyObject* ve = tuple_of(velocity, 2, "velocity");
    PyObject* lin = tuple_of(PyTuple_GET_ITEM(ve, 0), 3, "linear velocity");
    PyObject* ang = tuple_of(PyTuple_GET_ITEM(ve, 1), 3, "angular velocity");
    PyObject* cmd = tuple_of(command, 3, "command");
    PyObject* rays = tuple_of(hits, 4, "hits");
    if (!PyDict_Check(friction.ptr())) throw std::invalid_argument("friction must be a dict");

    const double px = item(pos, 0), py_ = item(pos, 1), pz = item(pos, 2);
    const double qx = item(orn, 0), qy = item(orn, 1), qz = item(orn, 2), qw = item(orn, 3);
    const double vx = item(lin, 0), vy = item(lin, 1), vz = item(lin, 2);
    const double wx = item(ang, 0), wy = item(ang, 1), wz = item(ang, 2);
    const double xx = qx * qx, yy = qy * qy, zz = qz * qz;
    const double xy = qx * qy, xz = qx * qz, yz = qy * qz, wxq = qw * qx, wyq = qw * qy, wzq = qw * qz;
    const double r00 = 1.0 - 2.0 * (yy + zz), r01 = 2.0 * (xy - wzq), r02 = 2.0 * (xz + wyq);
    const double r10 = 2.0 * (xy + wzq), r11 = 1.0 - 2.0 * (xx + zz), r12 = 2.0 * (yz - wxq);
    const double r20 = 2.0 * (xz - wyq), r21 = 2.0 * (yz + wxq), r22 = 1.0 - 2.0 * (xx + yy);
    const double cvx = item(cmd, 0), cvy = item(cmd, 1), cwz = item(cmd, 2);
    double hn = hypot_(r00, r10).cast<double>();
    if (hn == 0.0) hn = 1.0;
    const double hx = r00 / hn, hy = r10 / hn;
    const double tvx = cvx * hx - cvy * hy, tvy = cvx * hy + cvy * hx;

    struct Hit {
      bool ground;
      PyObject* id;
      double fraction, x, y, z, nx, ny, nz;
    };
    std::array<Hit, 4> found{};
    // Stance: the mean height of the ground found, summed in leg order from 0.0 as Python's sum() does.
    double ground_sum = 0.0;
    int grounds = 0;
    for (Py_ssize_t i = 0; i < 4; ++i) {
      PyObject* hit = tuple_of(PyTuple_GET_ITEM(rays, i), 5, "a hit");
      Hit& h = found[static_cast<std::size_t>(i)];
      h.id = PyTuple_GET_ITEM(hit, 0);
      const long id = PyLong_AsLong(h.id);
      if (id == -1 && PyErr_Occurred()) throw py::error_already_set();
      h.ground = id >= 0 && id != body;
      if (!h.ground) continue;
      PyObject* point = tuple_of(PyTuple_GET_ITEM(hit, 3), 3, "a hit position");
      PyObject* normal = tuple_of(PyTuple_GET_ITEM(hit, 4), 3, "a hit normal");
      h.fraction = item(hit, 2);
      h.x = item(point, 0), h.y = item(point, 1), h.z = item(point, 2);
      h.nx = item(normal, 0), h.ny = item(normal, 1), h.nz = item(normal, 2);
      ground_sum += h.z;
      ++grounds;
    }
    const double mean_ground = grounds ? ground_sum / grounds : 0.0;

    std::array<double, 4> legs{};
    double fx = 0.0, fy = 0.0, fz = 0.0, tx = 0.0, ty = 0.0, tz = 0.0;
    for (std::size_t i = 0; i < 4; ++i) {
      const Hit& h = found[i];
      if (!h.ground) continue;
      double rest = p_.rest + mean_ground - h.z;
      rest = rest < p_.min_length ? p_.min_length : (rest > p_.reach ? p_.reach : rest);
      const double lx = p_.hips[i][0], ly = p_.hips[i][1], lz = p_.hips[i][2];
      const double ox = r00 * lx + r01 * ly + r02 * lz;
      const double oy = r10 * lx + r11 * ly + r12 * lz;
      const double oz = r20 * lx + r21 * ly + r22 * lz;
      const double hvx = vx + wy * oz - wz * oy, hvy = vy + wz * ox - wx * oz, hvz = vz + wx * oy - wy * ox;
      const double length = p_.ray_start + h.fraction * p_.ray_length;
      double push = p_.stiffness * (rest - length) - p_.damping * (hvx * r02 + hvy * r12 + hvz * r22);
      push = push < 0.0 ? 0.0 : (push > p_.max_push ? p_.max_push : push);
      legs[i] = push;
      const double nx = h.nx, ny = h.ny, nz = h.nz;
      const double along = r02 * nx + r12 * ny + r22 * nz;
      const double normal_load = along > 0.0 ? push * along : 0.0;
      const double ex = tvx - cwz * oy - hvx, ey = tvy + cwz * ox - hvy, ez = -hvz;
      const double en = ex * nx + ey * ny + ez * nz;
      double gx = p_.share * (ex - en * nx), gy = p_.share * (ey - en * ny), gz = p_.share * (ez - en * nz);
      if (nz > 0.5) {
        const double hold = normal_load / nz;
        gx -= hold * nz * nx + push * (r02 - along * nx);
        gy -= hold * nz * ny + push * (r12 - along * ny);
        gz += hold * (1.0 - nz * nz) - push * (r22 - along * nz);
      }
      double mu = p_.default_friction;
      if (PyObject* given = PyDict_GetItemWithError(friction.ptr(), h.id)) {
        mu = PyFloat_AsDouble(given);
        if (mu == -1.0 && PyErr_Occurred()) throw py::error_already_set();
      } else if (PyErr_Occurred()) {
        throw py::error_already_set();
      }
      double limit = mu * normal_load;
      if (limit > p_.traction_max) limit = p_.traction_max;
      const double magnitude = std::sqrt(gx * gx + gy * gy + gz * gz);
      if (magnitude > limit) {
        const double scale = limit / magnitude;
        gx = gx * scale, gy = gy * scale, gz = gz * scale;
      }
      const double ffx = push * r02 + gx, ffy = push * r12 + gy, ffz = push * r22 + gz;
      const double rx = h.x - px, ry = h.y - py_, rz = h.z - pz;
      fx = fx + ffx, fy = fy + ffy, fz = fz + ffz;
      tx += ry * ffz - rz * ffy;
      ty += rz * ffx - rx * ffz;
      tz += rx * ffy - ry * ffx;
    }
    return py::make_tuple(fx, fy, fz, tx, ty, tz, legs[0], legs[1], legs[2], legs[3]);
  }

 private:
  LegParameters p_;
  py::object hypot_;
};

}  // namespace

PYBIND11_MODULE(_legs, m) {
  m.doc() = "The leg forces of navverse.sim.spot's legged model, one physics step at a time.";
  py::class_<LegModel>(m, "LegModel")
      .def(py::init<const std::array<std::array<double, 3>, 4>&, double, double, double, double, double, double,
                    double, double, double, double, double>(),
           py::arg("hips"), py::arg("share"), py::arg("stiffness"), py::arg("damping"), py::arg("max_push"),
           py::arg("rest"), py::arg("min_length"), py::arg("reach"), py::arg("ray_start"), py::arg("ray_length"),
           py::arg("traction_max"), py::arg("default_friction"))
      .def("forces", &LegModel::forces, py::arg("state"), py::arg("velocity"), py::arg("command"),
           py::arg("hits"), py::arg("friction"), py::arg("body"));
}

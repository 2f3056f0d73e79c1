#include "crowd.h"

#include <DetourAlloc.h>
#include <DetourCommon.h>
#include <dlfcn.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

namespace navverse {

namespace {

constexpr unsigned short kCrowdWalkFlag = 1u << 15;  // every polygon; filter i excludes flag 1 << i
constexpr double kVerticalReach = 2.0;                // half height of the box searched for the mesh

bool finite(const Vec3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

// RecastNavigation 1.5.1 (the Debian/Ubuntu package) asserts `npath < m_maxPath` when DetourCrowd
// gives an agent a corridor of exactly the longest length it allows, which the corridor then holds
// within its buffer (later releases assert `<=`): a long walk across a city aborted the process.
// Where the library was built with its assertions, this handler lets that one pass and aborts on any
// other, as assert() does.
void detourAssertFailed(const char* expression, const char* file, int line) {
  if (std::strcmp(expression, "npath < m_maxPath") == 0) return;
  std::fprintf(stderr, "%s:%d: Detour assertion failed: %s\n", file, line, expression);
  std::abort();
}

using AssertFailFunc = void(const char*, const char*, int);

// Installs the handler through the library's own hook, found at run time: a library built without
// assertions (NDEBUG) has no hook and needs none.
void installAssertHandler() {
  static const bool installed = [] {
    Dl_info info;
    if (dladdr(reinterpret_cast<void*>(&dtAllocNavMesh), &info) == 0 || info.dli_fname == nullptr) return false;
    void* library = dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD);
    if (library == nullptr) return false;
    using Setter = void (*)(AssertFailFunc*);
    auto set = reinterpret_cast<Setter>(dlsym(library, "_Z21dtAssertFailSetCustomPFvPKcS0_iE"));
    if (set != nullptr) set(&detourAssertFailed);
    dlclose(library);
    return set != nullptr;
  }();
  (void)installed;
}

}  // namespace

Crowd::Crowd(const std::string& navmesh, int maxAgents, double maxAgentRadius,
             const std::vector<std::vector<int>>& excluded, const std::vector<std::vector<double>>& costs)
    : mesh_(NavMesh::fromBytes(navmesh)) {
  installAssertHandler();
  const int filters = static_cast<int>(excluded.size());
  if (filters < 1 || filters > 15) throw NavError("a crowd needs 1 to 15 filters");
  if (!costs.empty() && static_cast<int>(costs.size()) != filters)
    throw NavError("a crowd's area costs must be given for every filter or for none");
  if (maxAgents < 1) throw NavError("a crowd needs room for at least one agent");
  if (!(maxAgentRadius > 0)) throw NavError("a crowd's largest agent radius must be positive");
  // The polygon flags of this copy say which filters exclude its area.
  std::vector<unsigned short> areaFlags(DT_MAX_AREAS, kCrowdWalkFlag);
  for (int f = 0; f < filters; ++f)
    for (int area : excluded[static_cast<std::size_t>(f)])
      if (area >= 0 && area < DT_MAX_AREAS) areaFlags[static_cast<std::size_t>(area)] |= (1u << f);
  dtNavMesh* nav = mesh_->detour();
  for (int i = 0; i < nav->getMaxTiles(); ++i) {
    const dtMeshTile* tile = static_cast<const dtNavMesh*>(nav)->getTile(i);
    if (!tile || !tile->header) continue;
    const dtPolyRef base = nav->getPolyRefBase(tile);
    for (int j = 0; j < tile->header->polyCount; ++j)
      nav->setPolyFlags(base | static_cast<dtPolyRef>(j), areaFlags[tile->polys[j].getArea()]);
  }
  crowd_ = dtAllocCrowd();
  if (!crowd_ || !crowd_->init(maxAgents, static_cast<float>(maxAgentRadius), nav)) {
    dtFreeCrowd(crowd_);
    throw std::bad_alloc();
  }
  for (int f = 0; f < filters; ++f) {
    dtQueryFilter* filter = crowd_->getEditableFilter(f);
    filter->setIncludeFlags(kCrowdWalkFlag);
    filter->setExcludeFlags(static_cast<unsigned short>(1u << f));
    for (int a = 0; a < DT_MAX_AREAS; ++a) {
      const bool given = !costs.empty() && a < static_cast<int>(costs[static_cast<std::size_t>(f)].size());
      filter->setAreaCost(a, given ? static_cast<float>(costs[static_cast<std::size_t>(f)][static_cast<std::size_t>(a)])
                                   : 1.0f);
    }
  }
  // Obstacle avoidance presets, coarse to fine (the values of Detour's own demo).
  for (int q = 0; q < 4; ++q) {
    dtObstacleAvoidanceParams params = *crowd_->getObstacleAvoidanceParams(q);
    params.velBias = 0.5f;
    params.adaptiveDivs = static_cast<unsigned char>(q < 2 ? 5 + q * 2 : 7);
    params.adaptiveRings = static_cast<unsigned char>(q < 1 ? 2 : 3);
    params.adaptiveDepth = static_cast<unsigned char>(q < 1 ? 1 : (q == 3 ? 3 : 2));
    crowd_->setObstacleAvoidanceParams(q, &params);
  }
}

Crowd::~Crowd() { dtFreeCrowd(crowd_); }

bool Crowd::locate(const Vec3& p, int filter, double reach, dtPolyRef* ref, float* nearest) const {
  *ref = 0;
  if (!finite(p) || !(reach > 0)) return false;
  float c[3];
  toRecast(p.data(), c);
  const float ext[3] = {static_cast<float>(reach), static_cast<float>(kVerticalReach), static_cast<float>(reach)};
  const dtQueryFilter* f = crowd_->getFilter(filter);
  if (!f) return false;
  const dtStatus status = crowd_->getNavMeshQuery()->findNearestPoly(c, ext, f, ref, nearest);
  return dtStatusSucceed(status) && *ref != 0;
}

int Crowd::addAgent(const Vec3& position, const CrowdAgentSpec& spec, double reach) {
  if (spec.filter < 0 || spec.filter >= DT_CROWD_MAX_QUERY_FILTER_TYPE) throw NavError("no such crowd filter");
  if (spec.avoidance_quality < 0 || spec.avoidance_quality > 3) throw NavError("avoidance quality is 0 to 3");
  dtPolyRef ref;
  float at[3];
  if (!locate(position, spec.filter, reach, &ref, at)) return -1;
  dtCrowdAgentParams params{};
  params.radius = static_cast<float>(spec.radius);
  params.height = static_cast<float>(spec.height);
  params.maxAcceleration = static_cast<float>(spec.max_acceleration);
  params.maxSpeed = static_cast<float>(spec.max_speed);
  params.collisionQueryRange = static_cast<float>(spec.collision_query_range);
  params.pathOptimizationRange = static_cast<float>(spec.path_optimization_range);
  params.separationWeight = static_cast<float>(spec.separation_weight);
  params.updateFlags = DT_CROWD_ANTICIPATE_TURNS | DT_CROWD_OBSTACLE_AVOIDANCE | DT_CROWD_SEPARATION |
                       DT_CROWD_OPTIMIZE_VIS | DT_CROWD_OPTIMIZE_TOPO;
  params.obstacleAvoidanceType = static_cast<unsigned char>(spec.avoidance_quality);
  params.queryFilterType = static_cast<unsigned char>(spec.filter);
  params.userData = nullptr;
  return crowd_->addAgent(at, &params);
}

const dtCrowdAgent* Crowd::agentAt(int agent) const {
  if (agent < 0 || agent >= crowd_->getAgentCount()) throw NavError("no such crowd agent");
  return crowd_->getAgent(agent);
}

void Crowd::removeAgent(int agent) {
  agentAt(agent);
  crowd_->removeAgent(agent);
}

bool Crowd::setTarget(int agent, const Vec3& target, double reach) {
  const dtCrowdAgent* a = agentAt(agent);
  if (!a->active) return false;
  dtPolyRef ref;
  float at[3];
  if (!locate(target, a->params.queryFilterType, reach, &ref, at)) return false;
  return crowd_->requestMoveTarget(agent, ref, at);
}

bool Crowd::setVelocity(int agent, const Vec3& velocity) {
  const dtCrowdAgent* a = agentAt(agent);
  if (!a->active || !finite(velocity)) return false;
  const Vec3 flat = {velocity[0], velocity[1], 0.0};
  float v[3];
  toRecast(flat.data(), v);
  return crowd_->requestMoveVelocity(agent, v);
}

bool Crowd::place(int agent, const Vec3& position, double reach) {
  dtCrowdAgent* a = crowd_->getEditableAgent(agent);
  if (!a || !a->active) return false;
  dtPolyRef ref;
  float at[3];
  if (!locate(position, a->params.queryFilterType, reach, &ref, at)) return false;
  a->corridor.reset(ref, at);
  a->boundary.reset();
  dtVcopy(a->npos, at);
  a->state = DT_CROWDAGENT_STATE_WALKING;
  return true;
}

void Crowd::update(double dt) {
  if (!(dt > 0) || !std::isfinite(dt)) throw NavError("a crowd step must be a positive time");
  crowd_->update(static_cast<float>(dt), nullptr);
}

int Crowd::maxAgents() const { return crowd_->getAgentCount(); }

bool Crowd::active(int agent) const { return agentAt(agent)->active; }

Vec3 Crowd::position(int agent) const {
  Vec3 out;
  fromRecast(agentAt(agent)->npos, out.data());
  return out;
}

Vec3 Crowd::velocity(int agent) const {
  Vec3 out;
  fromRecast(agentAt(agent)->vel, out.data());
  return out;
}

int Crowd::targetState(int agent) const { return agentAt(agent)->targetState; }

int Crowd::areaAt(int agent) const {
  const dtCrowdAgent* a = agentAt(agent);
  const dtPolyRef ref = a->corridor.getFirstPoly();
  const dtMeshTile* tile = nullptr;
  const dtPoly* poly = nullptr;
  if (!a->active || !ref || dtStatusFailed(mesh_->detour()->getTileAndPolyByRef(ref, &tile, &poly))) return -1;
  return poly->getArea();
}

}  // namespace navverse

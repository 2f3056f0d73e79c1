// Agents walking a navmesh with DetourCrowd: paths along the mesh, local steering round each other
// (velocity-obstacle sampling) and separation. World coordinates (z up), as everywhere in navverse::.
#pragma once

#include <DetourCrowd.h>

#include <memory>
#include <string>
#include <vector>

#include "../../nav/csrc/navmesh.h"

namespace navverse {

// What an agent is: its size, how fast it walks and accelerates, which filter (areas it may walk)
// it uses, how strongly it keeps apart from others.
struct CrowdAgentSpec {
  double radius = 0.3;
  double height = 1.7;
  double max_speed = 1.4;
  double max_acceleration = 4.0;
  double separation_weight = 2.0;
  double collision_query_range = 3.6;
  double path_optimization_range = 9.0;
  int filter = 0;
  int avoidance_quality = 2;  // one of the crowd's obstacle avoidance presets, 0 (coarse) .. 3 (fine)
};

class Crowd {
 public:
  // A crowd on its own copy of a navmesh (`navmesh` as NavMesh::toBytes writes it). Filter i walks
  // every area but `excluded[i]` and prefers areas by `costs[i]` (DT_MAX_AREAS entries, or empty: 1).
  Crowd(const std::string& navmesh, int maxAgents, double maxAgentRadius,
        const std::vector<std::vector<int>>& excluded, const std::vector<std::vector<double>>& costs);
  ~Crowd();
  Crowd(const Crowd&) = delete;
  Crowd& operator=(const Crowd&) = delete;

  // The agent's index, or -1 when `position` is not within reach of its filter's mesh or the crowd
  // is full. `reach` is the horizontal half size of the box searched for the mesh.
  int addAgent(const Vec3& position, const CrowdAgentSpec& spec, double reach);
  void removeAgent(int agent);
  // Walk to the mesh point nearest `target` (within `reach`); false if there is none.
  bool setTarget(int agent, const Vec3& target, double reach);
  // Move at `velocity` (its horizontal part) instead of along a path, until a target is set.
  bool setVelocity(int agent, const Vec3& velocity);
  // Put the agent at the mesh point nearest `position`, keeping its target (a body another simulation
  // moves, the robot); false if there is none within `reach`.
  bool place(int agent, const Vec3& position, double reach);
  void update(double dt);

  int maxAgents() const;
  bool active(int agent) const;
  Vec3 position(int agent) const;
  Vec3 velocity(int agent) const;
  // DetourCrowd's request state: 0 none, 1 failed, 2 valid, 3-5 being planned, 6 moving by velocity.
  int targetState(int agent) const;
  // The area of the polygon the agent stands on (-1 if none).
  int areaAt(int agent) const;

 private:
  const dtCrowdAgent* agentAt(int agent) const;
  bool locate(const Vec3& p, int filter, double reach, dtPolyRef* ref, float* nearest) const;

  std::unique_ptr<NavMesh> mesh_;
  dtCrowd* crowd_ = nullptr;
};

}  // namespace navverse

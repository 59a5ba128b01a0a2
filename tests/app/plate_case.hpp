// A case the limit and campaign tests share: a coarse ball onto a plate, each run under a second.
#pragma once

namespace tc::test {

// An aluminium ball (4 mm) onto an aluminium plate of thickness tb, coarse: it perforates a
// 1 mm plate from between 1,000 and 1,400 m/s (single runs: not at 1,000, perforated at 1,400;
// a 2 mm plate not at 1,400), each run under a second. Christiansen's equation stands beside it
// as if the plate were the bumper of a Whipple shield with a 2 mm wall 30 mm behind.
inline constexpr const char* k_plate = R"yaml(name: limit-plate
parameters:
  v: 1000
  tb: 1.0e-3
end_time: 4.0e-6
materials:
  al: {from: al6061-t6}
bodies:
  - name: ball
    material: al
    mesh: {sphere: {radius: 2.0e-3, cells_across: 4}}
    transform: [{translate: [0, 0, 2.0e-3]}]
    velocity: [0, 0, "= -v"]
  - name: plate
    material: al
    mesh: {box: {size: [12.0e-3, 12.0e-3, "= tb"], cells: [8, 8, "= max(1, round(tb / 1.0e-3))"]}}
    transform: [{translate: [0, 0, "= -tb / 2"]}]
contact: {enabled: true, broadphase: grid}
fracture: {enabled: true}
output: {interval: 4.0e-6, fields: [velocity]}
reference:
  - name: plate perforated
    measure: perforated
    body: plate
    plane: {point: [0, 0, "= -tb"], normal: [0, 0, -1]}
    within: 6.0e-3
shield_equation:
  projectile: ball
  bumper: plate
  diameter: 4.0e-3
  speed: "= v"
  bumper_thickness: "= tb"
  standoff: 30.0e-3
  wall_thickness: 2.0e-3
  wall_yield: 276.0e6
  verdict: plate perforated
)yaml";

}  // namespace tc::test

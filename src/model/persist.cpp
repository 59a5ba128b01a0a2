#include "tetcontact/model/persist.hpp"

namespace tc {

void persist(Archive& ar, Surface& s) {
  ar(s.body, s.faces, s.face_tet, s.edges, s.nodes, s.node_face_offsets, s.node_faces,
     s.mean_edge_length, s.max_edge_length);
}

void persist(Archive& ar, ParticleMatter& pm) {
  ar(pm.h, pm.spacing, pm.rho, pm.vol0, pm.vol, pm.s, pm.p, pm.q, pm.eps_p, pm.ductile,
     pm.ductile_floor, pm.w_plastic, pm.w_viscous, pm.sound2, pm.trace_d, pm.temperature,
     pm.material, pm.damage, pm.plane_impulse);
}

void persist(Archive& ar, State& st) {
  ar.section("state");
  ar(st.x, st.v, st.v_star, st.x_star, st.f, st.m, st.bc_impulse, st.wall_impulse,
     st.contact_impulse);
  ar(st.vol0, st.vol, st.s, st.p, st.q, st.e_int, st.eps_p, st.ductile, st.ductile_floor,
     st.w_plastic, st.w_viscous, st.sound2, st.trace_d, st.temperature, st.tet_material, st.damage);
  ar(st.first_particle, st.particle_radius, st.particle_energy, st.particle_tet, st.particle_planes,
     st.sph, st.surfaces, st.t, st.dt, st.dt_prev, st.step);
}

void persist(Archive& ar, ImpulseLedger& l) {
  ar(l.work, l.impulse, l.work_ahead, l.impulse_ahead);
}

void persist(Archive& ar, Sample& s) {
  ar(s.step, s.t, s.dt, s.kinetic, s.internal, s.plastic_work, s.viscous_work, s.boundary, s.walls,
     s.contact, s.planes, s.contact_heat, s.contact_force, s.contacts, s.damaged, s.destroyed,
     s.particles, s.particle_mass, s.total, s.balance_error, s.mass);
  ar(s.momentum, s.momentum_scale, s.wall_force, s.final);
}

void persist(Archive& ar, StepProfile& p) {
  ar(p.stages);
}

}  // namespace tc

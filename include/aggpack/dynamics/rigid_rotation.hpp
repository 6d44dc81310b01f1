#pragma once
// The rotation of a rigid body (a grain of several spheres) between two kicks of its angular
// momentum: the free rotor, integrated by splitting its kinetic energy into the parts of the
// three principal axes, each of which is an exact rotation about that axis.
#include "aggpack/core/quaternion.hpp"
#include "aggpack/core/vec3.hpp"

namespace aggpack {

// Turns the body of orientation `orientation` (body frame to space) and angular momentum
// `angular_momentum` (space frame) freely for `dt`, its principal moments of inertia along
// the body frame's axes given as their inverses. The splitting is NO_SQUISH's (Miller,
// Eleftheriou, Pattnaik, Ndirango, Newns and Martyna, J. Chem. Phys. 116, 8649, 2002; Dullweber,
// Leimkuhler and McLachlan, J. Chem. Phys. 107, 5840, 1997): the exact rotations about the body
// axes z, y, x, y, z for dt/2, dt/2, dt, dt/2, dt/2. Symplectic, time-reversible and of second
// order: over any number of steps the energy stays within O((ω dt)²) of its start without
// drifting, and the angular momentum in space, which no part changes, is kept exactly.
void rotate_freely(Quaternion& orientation, const Vec3& angular_momentum, const Vec3& inverse_inertia, double dt);

// The angular velocity in space of a body of that orientation (as a matrix) and angular momentum.
[[nodiscard]] Vec3 angular_velocity_of(const RotationMatrix& orientation, const Vec3& angular_momentum,
                                       const Vec3& inverse_inertia);

}  // namespace aggpack

// Named initial velocity fields (set on the faces at their exact positions).
//
//   rest          v = 0
//   uniform       v = initial.velocity
//   taylor_green  2D: u =  U sin(kx) cos(ky),  v = -U cos(kx) sin(ky), p = rho U^2/4 (cos 2kx + cos
//   2ky)
//                 3D: u =  U sin(kx) cos(ky) cos(kz), v = -U cos(kx) sin(ky) cos(kz), w = 0
//                 with k = 2 pi / L_x (the box must be a cube in the used directions)
//   couette       u = U (y - y0) / L_y: the steady state of walls at y moving at 0 and U
//   poiseuille    u = U 4 (y - y0)(L_y - (y - y0)) / L_y^2: parabola of centreline speed U
//   shear         u = U (2 (y - y0) / L_y - 1): linear shear between walls at -U and +U
#pragma once

#include "config/config.hpp"
#include "time/flow_state.hpp"

namespace efsi {

void set_initial_condition(const Config& config, const Decomposition& dec, FlowState& state);

} // namespace efsi

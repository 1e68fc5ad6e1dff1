// The shape a body is made from: its config's `shape` with centre, radius, axes and
// orientation (interface/shapes.hpp). Used to initialise the body and, for a membrane's
// reference map, as its reference surface (map_projection).
#pragma once

#include "config/body_config.hpp"
#include "interface/shapes.hpp"

#include <memory>

namespace efsi {

/// The body's shape; null for a mask (shape = "mask": no analytic surface).
std::unique_ptr<Shape> make_body_shape(const BodyConfig& body);

} // namespace efsi

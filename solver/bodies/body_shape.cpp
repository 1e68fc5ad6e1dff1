#include "bodies/body_shape.hpp"

namespace efsi {

std::unique_ptr<Shape> make_body_shape(const BodyConfig& b) {
    const Matrix3 rot = b.angle != 0 ? axis_angle_rotation(b.axis, b.angle) : identity_rotation();
    switch (b.shape) {
    case BodyShape::Sphere:
        return make_sphere(b.centre, b.radius);
    case BodyShape::Ellipsoid:
        return make_ellipsoid(b.centre, b.semi_axes, rot);
    case BodyShape::Biconcave: {
        EvansFungCoefficients k;
        k.r0 = b.radius;
        // The smoothed (membrane) profile needs a distance; the sharp one only the sign.
        return b.interface == InterfaceKind::Smoothed ? make_biconcave_distance(b.centre, rot, k)
                                                      : make_biconcave_disc(b.centre, rot, k);
    }
    case BodyShape::Tube:
        return make_tube(b.centre, 0.5 * b.lumen_diameter);
    case BodyShape::Cylinder:
        return make_cylinder(b.centre, b.radius, rot);
    case BodyShape::Box:
        return make_box(b.centre, b.half_sizes, rot);
    case BodyShape::Slab:
        return make_slab(b.centre, b.normal, b.thickness);
    case BodyShape::Mask:
        return nullptr;
    }
    return nullptr;
}

} // namespace efsi

#include "membrane/membrane_law.hpp"

#include "core/error.hpp"
#include "membrane/neo_hookean.hpp"
#include "membrane/skalak.hpp"

namespace efsi {

std::unique_ptr<MembraneLaw> make_membrane_law(const std::string& name, real Es, real alpha) {
    if (name == "neo_hookean") return std::make_unique<NeoHookeanLaw>(Es);
    if (name == "skalak") return std::make_unique<SkalakLaw>(Es, alpha);
    throw InputError("membrane law '" + name + "' is unknown (neo_hookean, skalak)");
}

} // namespace efsi

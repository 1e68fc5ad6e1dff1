#include "membrane/membrane_law.hpp"

#include "core/error.hpp"
#include "membrane/neo_hookean.hpp"
#include "membrane/skalak.hpp"

namespace efsi {

std::unique_ptr<MembraneLaw> make_membrane_law(MembraneLawKind law, real Es, real alpha) {
    switch (law) {
    case MembraneLawKind::NeoHookean:
        return std::make_unique<NeoHookeanLaw>(Es);
    case MembraneLawKind::Skalak:
        return std::make_unique<SkalakLaw>(Es, alpha);
    }
    throw InputError("membrane law: unknown kind");
}

std::unique_ptr<MembraneLaw> make_membrane_law(const std::string& name, real Es, real alpha) {
    return make_membrane_law(parse_membrane_law(name, "membrane law"), Es, alpha);
}

} // namespace efsi

// Run state that is not a grid field, in the form the checkpoint stores it: named 1D arrays
// of doubles and of unsigned 64-bit integers that every rank holds alike (the adhesion's
// receptors, bonds and counters). A module that owns such state writes it into a record
// (save) and takes it back (restore); the checkpoint stores the record as one HDF5 group
// without knowing what it holds (io/checkpoint.hpp).
#pragma once

#include "core/error.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace efsi {

struct StateRecord {
    /// What the record holds, in words (stored with it, named when a checkpoint holds a
    /// record its case has no use for).
    std::string description;
    std::map<std::string, std::vector<double>> reals;
    std::map<std::string, std::vector<std::uint64_t>> integers;

    /// The array `name` (InputError naming it when absent, or when it does not hold
    /// `size` values; any size when `size` is npos).
    const std::vector<double>& real_array(const std::string& name, std::size_t size = npos) const {
        return find(reals, name, size);
    }
    const std::vector<std::uint64_t>& integer_array(const std::string& name,
                                                    std::size_t size = npos) const {
        return find(integers, name, size);
    }
    static constexpr std::size_t npos = static_cast<std::size_t>(-1);

  private:
    template <class Map>
    static const typename Map::mapped_type& find(const Map& m, const std::string& name,
                                                 std::size_t size) {
        const auto it = m.find(name);
        if (it == m.end()) throw InputError("has no array '" + name + "'");
        if (size != npos && it->second.size() != size)
            throw InputError("array '" + name + "' holds " + std::to_string(it->second.size()) +
                             " values where " + std::to_string(size) + " are expected");
        return it->second;
    }
};

} // namespace efsi

#include "config/reader.hpp"

#include "core/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace efsi {

KeyCatalogue& KeyCatalogue::instance() {
    static KeyCatalogue c;
    return c;
}

void KeyCatalogue::add(KeyDoc doc) {
    if (!documenting) return;
    for (const auto& k : keys_)
        if (k.key == doc.key) return;
    keys_.push_back(std::move(doc));
}

std::string Range::describe() const {
    const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
    if (!has_lo && !has_hi) return "any";
    if (has_lo && !has_hi) return fmt::format("{} {}", lo_open ? ">" : ">=", lo);
    if (!has_lo) return fmt::format("<= {}", hi);
    return fmt::format("{}{}, {}]", lo_open ? "(" : "[", lo, hi);
}

bool Range::contains(real x) const {
    if (std::isnan(x)) return false;
    if (lo_open ? !(x > lo) : !(x >= lo)) return false;
    return x <= hi;
}

TableReader::TableReader(toml::table* table, std::string path)
    : table_(table), path_(std::move(path)) {}

toml::node* TableReader::get(const std::string& key) {
    read_.push_back(key);
    return table_ ? table_->get(key) : nullptr;
}

bool TableReader::has(const std::string& key) const {
    return table_ && table_->contains(key);
}

void TableReader::document(const std::string& key, const std::string& type, const std::string& unit,
                           const std::string& deflt, const std::string& range,
                           const std::string& meaning) {
    KeyCatalogue::instance().add({full(key), type, unit, deflt, range, meaning});
}

static std::string fmt_real(real x) {
    return fmt::format("{}", x);
}

real TableReader::number(const std::string& key, std::optional<real> deflt, Range range,
                         const std::string& unit, const std::string& meaning) {
    document(key, "float", unit, deflt ? fmt_real(*deflt) : "required", range.describe(), meaning);
    toml::node* n = get(key);
    real value = 0;
    if (!n) {
        if (!deflt) {
            if (KeyCatalogue::instance().documenting) return 0;
            throw InputError(fmt::format("{}: required key is missing ({})", full(key), meaning));
        }
        value = *deflt;
    } else if (auto f = n->value<double>(); f && (n->is_floating_point() || n->is_integer())) {
        value = *f;
    } else {
        throw InputError(fmt::format("{}: expected a number [{}], got {}", full(key), unit,
                                     toml::impl::node_type_friendly_names[int(n->type())]));
    }
    if (!std::isfinite(value))
        throw InputError(fmt::format("{} = {}: must be a finite number", full(key), value));
    if (!range.contains(value))
        throw InputError(
            fmt::format("{} = {}: out of range (allowed: {})", full(key), value, range.describe()));
    return value;
}

int TableReader::integer(const std::string& key, std::optional<int> deflt, Range range,
                         const std::string& meaning) {
    document(key, "integer", "-", deflt ? std::to_string(*deflt) : "required", range.describe(),
             meaning);
    toml::node* n = get(key);
    long long value = 0;
    if (!n) {
        if (!deflt) {
            if (KeyCatalogue::instance().documenting) return 0;
            throw InputError(fmt::format("{}: required key is missing ({})", full(key), meaning));
        }
        value = *deflt;
    } else if (n->is_integer()) {
        value = *n->value<long long>();
    } else {
        throw InputError(fmt::format("{}: expected an integer", full(key)));
    }
    if (!range.contains(real(value)) || value > std::numeric_limits<int>::max() ||
        value < std::numeric_limits<int>::min())
        throw InputError(
            fmt::format("{} = {}: out of range (allowed: {})", full(key), value, range.describe()));
    return int(value);
}

bool TableReader::boolean(const std::string& key, bool deflt, const std::string& meaning) {
    document(key, "bool", "-", deflt ? "true" : "false", "true, false", meaning);
    toml::node* n = get(key);
    if (!n) return deflt;
    if (!n->is_boolean()) throw InputError(fmt::format("{}: expected true or false", full(key)));
    return *n->value<bool>();
}

std::string TableReader::string(const std::string& key, std::optional<std::string> deflt,
                                const std::vector<std::string>& choices,
                                const std::string& meaning) {
    std::string allowed;
    for (const auto& c : choices)
        allowed += (allowed.empty() ? "" : ", ") + c;
    document(key, "string", "-", deflt ? "\"" + *deflt + "\"" : "required",
             choices.empty() ? "any" : allowed, meaning);
    toml::node* n = get(key);
    std::string value;
    if (!n) {
        if (!deflt) {
            if (KeyCatalogue::instance().documenting) return choices.empty() ? "" : choices[0];
            throw InputError(fmt::format("{}: required key is missing ({})", full(key), meaning));
        }
        value = *deflt;
    } else if (n->is_string()) {
        value = *n->value<std::string>();
    } else {
        throw InputError(fmt::format("{}: expected a string", full(key)));
    }
    if (!choices.empty() && std::find(choices.begin(), choices.end(), value) == choices.end())
        throw InputError(
            fmt::format("{} = \"{}\": unknown value (allowed: {})", full(key), value, allowed));
    return value;
}

const toml::array* TableReader::triple(const std::string& key, const std::string& type,
                                       const std::string& unit, const std::string& deflt_text,
                                       const Range& range, const std::string& meaning,
                                       bool has_default) {
    document(key, type, unit, has_default ? deflt_text : "required", range.describe(), meaning);
    toml::node* n = get(key);
    if (!n) {
        if (!has_default && !KeyCatalogue::instance().documenting)
            throw InputError(fmt::format("{}: required key is missing ({})", full(key), meaning));
        return nullptr;
    }
    const toml::array* a = n->as_array();
    if (!a || a->size() != 3)
        throw InputError(fmt::format("{}: expected an array of 3 {}{}", full(key),
                                     type == "float[3]" ? "numbers" : "integers",
                                     unit == "-" ? "" : " [" + unit + "]"));
    return a;
}

Real3 TableReader::vector3(const std::string& key, std::optional<Real3> deflt, Range range,
                           const std::string& unit, const std::string& meaning) {
    const std::string text =
        deflt ? fmt::format("[{}, {}, {}]", (*deflt)[0], (*deflt)[1], (*deflt)[2]) : "";
    const toml::array* a = triple(key, "float[3]", unit, text, range, meaning, deflt.has_value());
    if (!a) return deflt ? *deflt : Real3{0, 0, 0};
    Real3 v{};
    for (int d = 0; d < 3; ++d) {
        const auto x = (*a)[d].value<double>();
        if (!x) throw InputError(fmt::format("{}[{}]: expected a number", full(key), d));
        v[d] = *x;
        check_element(key, d, v[d], range);
    }
    return v;
}

Int3 TableReader::ivector3(const std::string& key, std::optional<Int3> deflt, Range range,
                           const std::string& meaning) {
    const std::string text =
        deflt ? fmt::format("[{}, {}, {}]", (*deflt)[0], (*deflt)[1], (*deflt)[2]) : "";
    const toml::array* a = triple(key, "integer[3]", "-", text, range, meaning, deflt.has_value());
    if (!a) return deflt ? *deflt : Int3{1, 1, 1};
    Int3 v{};
    for (int d = 0; d < 3; ++d) {
        if (!(*a)[d].is_integer())
            throw InputError(fmt::format("{}[{}]: expected an integer", full(key), d));
        const long long x = *(*a)[d].value<long long>();
        check_element(key, d, real(x), range);
        v[d] = int(x);
    }
    return v;
}

void TableReader::check_element(const std::string& key, int d, real value,
                                const Range& range) const {
    if (!std::isfinite(value))
        throw InputError(fmt::format("{}[{}] = {}: must be a finite number", full(key), d, value));
    if (!range.contains(value))
        throw InputError(fmt::format("{}[{}] = {}: out of range (allowed: {})", full(key), d, value,
                                     range.describe()));
}

TableReader TableReader::sub(const std::string& key, const std::string& meaning) {
    KeyCatalogue::instance().add({full(key), "table", "-", "-", "-", meaning});
    toml::node* n = get(key);
    if (n && !n->is_table())
        throw InputError(fmt::format("{}: expected a table ([{}])", full(key), full(key)));
    return TableReader(n ? n->as_table() : nullptr, full(key));
}

std::vector<TableReader> TableReader::tables(const std::string& key, const std::string& meaning) {
    KeyCatalogue::instance().add({full(key) + "[]", "array of tables", "-", "none", "-", meaning});
    std::vector<TableReader> out;
    toml::node* n = get(key);
    if (KeyCatalogue::instance().documenting) {
        out.emplace_back(nullptr, full(key) + "[]");
        return out;
    }
    if (!n) return out;
    toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables())
        throw InputError(
            fmt::format("{}: expected an array of tables ([[{}]] sections)", full(key), full(key)));
    for (std::size_t i = 0; i < a->size(); ++i)
        out.emplace_back((*a)[i].as_table(), fmt::format("{}[{}]", full(key), i));
    return out;
}

void TableReader::finish() const {
    finish_except({});
}

void TableReader::finish_except(std::initializer_list<std::string_view> later) const {
    if (!table_) return;
    for (auto&& [k, v] : *table_) {
        const std::string key(k.str());
        if (std::find(later.begin(), later.end(), key) != later.end()) continue;
        if (std::find(read_.begin(), read_.end(), key) == read_.end())
            throw InputError(fmt::format("{}: unknown key (check the spelling; "
                                         "docs/case-reference.md lists every key)",
                                         full(key)));
    }
}

} // namespace efsi

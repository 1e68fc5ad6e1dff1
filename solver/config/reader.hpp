// Typed, checked reading of one TOML table: every key read is declared with its type,
// unit, default and range (that declaration is also what docs/case-reference.md is
// generated from), and keys nobody asked for are errors naming the key.
#pragma once

#include "core/types.hpp"

#include <toml++/toml.h>

#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace efsi {

struct KeyDoc {
    std::string key;     ///< dotted path, e.g. "time.cfl"
    std::string type;    ///< float, integer, string, bool, float[3], ...
    std::string unit;    ///< SI unit or "-"
    std::string deflt;   ///< default, or "required"
    std::string range;   ///< allowed values
    std::string meaning; ///< one line
};

/// Collects the key documentation of every reader when enabled.
class KeyCatalogue {
  public:
    static KeyCatalogue& instance();
    void add(KeyDoc doc);
    const std::vector<KeyDoc>& keys() const { return keys_; }
    bool documenting = false;

  private:
    std::vector<KeyDoc> keys_;
};

struct Range {
    real lo = -std::numeric_limits<real>::infinity();
    real hi = std::numeric_limits<real>::infinity();
    bool lo_open = false; ///< lo excluded
    static Range positive() { return {0, std::numeric_limits<real>::infinity(), true}; }
    static Range non_negative() { return {0, std::numeric_limits<real>::infinity(), false}; }
    static Range closed(real a, real b) { return {a, b, false}; }
    std::string describe() const;
    bool contains(real x) const;
};

class TableReader {
  public:
    /// `path` is the dotted name of the table ("" for the root).
    TableReader(toml::table* table, std::string path);

    real number(const std::string& key, std::optional<real> deflt, Range range,
                const std::string& unit, const std::string& meaning);
    int integer(const std::string& key, std::optional<int> deflt, Range range,
                const std::string& meaning);
    bool boolean(const std::string& key, bool deflt, const std::string& meaning);
    std::string string(const std::string& key, std::optional<std::string> deflt,
                       const std::vector<std::string>& choices, const std::string& meaning);
    Real3 vector3(const std::string& key, std::optional<Real3> deflt, Range range,
                  const std::string& unit, const std::string& meaning);
    Int3 ivector3(const std::string& key, std::optional<Int3> deflt, Range range,
                  const std::string& meaning);

    bool has(const std::string& key) const;
    /// Sub-table reader; an absent sub-table reads as empty (all defaults).
    TableReader sub(const std::string& key, const std::string& meaning);
    /// Readers of an array of tables (`[[key]]`), named key[0], key[1], ... In documenting
    /// mode one empty reader is returned so that the entries' keys get documented.
    std::vector<TableReader> tables(const std::string& key, const std::string& meaning);
    /// Error if the table holds keys that were not read.
    void finish() const;
    /// finish(), but the keys in `later` may still be read afterwards.
    void finish_except(std::initializer_list<std::string_view> later) const;
    std::string full(const std::string& key) const {
        return path_.empty() ? key : path_ + "." + key;
    }

  private:
    toml::node* get(const std::string& key);
    /// Document a 3-array key and return its array (null when absent and defaulted);
    /// throws when it is required and missing, or not an array of 3.
    const toml::array* triple(const std::string& key, const std::string& type,
                              const std::string& unit, const std::string& deflt_text,
                              const Range& range, const std::string& meaning, bool has_default);
    void check_element(const std::string& key, int d, real value, const Range& range) const;
    void document(const std::string& key, const std::string& type, const std::string& unit,
                  const std::string& deflt, const std::string& range, const std::string& meaning);
    toml::table* table_; ///< null for an absent table (reads as empty)
    std::string path_;
    std::vector<std::string> read_;
};

} // namespace efsi

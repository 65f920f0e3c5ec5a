// rcsim — typed, line-numbered access to one YAML mapping of a configuration file: the one strict
// reader of every file rcsim reads (the scenario, its `motion:` section, ...).
//
// Every read names the file and line of the offending value on error, and finish() rejects keys
// nobody read (a misspelt key must not be silently ignored — VCML fails on unused properties too).
// Keys are named by their full path in messages: `motion.commands[2].axis`.
#pragma once

#include "models/plumbing/config_error.h"

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace rcsim {

class YamlMap {
public:
    /// `node` must be a mapping (or null/absent: then every get() returns its default).
    YamlMap(YAML::Node node, std::string file, std::string context);

    bool has(const std::string& key) const;
    /// The value of `key` converted to T, or `fallback` when absent.
    template <typename T> T get(const std::string& key, const T& fallback);
    /// The value of `key` converted to T; an error naming the key when absent.
    template <typename T> T require(const std::string& key);
    /// A numeric value checked against [lo, hi].
    double number(const std::string& key, double fallback, double lo, double hi);
    /// A required numeric value checked against [lo, hi].
    double require_number(const std::string& key, double lo, double hi);
    /// A whole number checked against [lo, hi] (`index: 1.7` is an error, not 1). `lo` and `hi`
    /// must be exact in a double (below 2^53).
    std::uint64_t integer(const std::string& key, std::uint64_t fallback, std::uint64_t lo, std::uint64_t hi);
    /// A string that must be one of `allowed` (`fallback` when absent).
    std::string choice(const std::string& key, const std::string& fallback,
                       std::initializer_list<const char*> allowed);
    /// A list of scalars converted to T, at most `max_items` long; empty when absent.
    template <typename T>
    std::vector<T> list(const std::string& key, std::size_t max_items = std::numeric_limits<std::size_t>::max());
    /// A list of mappings (`key[i].` in messages), at most `max_items` long; empty when absent.
    /// Each element must be finish()ed by its reader.
    std::vector<YamlMap> maps(const std::string& key,
                              std::size_t max_items = std::numeric_limits<std::size_t>::max());
    /// The raw child node (marked as read); an undefined node when absent.
    YAML::Node child(const std::string& key);
    /// A nested mapping.
    YamlMap map(const std::string& key);

    /// Throws ConfigError for the first key that was never read.
    void finish() const;

    [[noreturn]] void fail(const YAML::Node& at, const std::string& message) const;
    [[noreturn]] void fail(const std::string& message) const { fail(node_, message); }
    const std::string& file() const { return file_; }
    const std::string& context() const { return context_; }
    /// This mapping's key path for messages: "motion.checks", "ports[0]", or "top level".
    std::string name() const;
    static int line_of(const YAML::Node& n) { return n.Mark().is_null() ? 0 : n.Mark().line + 1; }

private:
    /// The child `key`, which must be a sequence of at most `max_items` (undefined when absent).
    YAML::Node sequence(const std::string& key, std::size_t max_items, const char* of);

    YAML::Node node_;
    std::string file_;
    std::string context_;
    mutable std::set<std::string> used_;
};

template <typename T> T YamlMap::get(const std::string& key, const T& fallback) {
    if (!has(key)) return fallback;
    return require<T>(key);
}

template <typename T> T YamlMap::require(const std::string& key) {
    YAML::Node v = child(key);
    if (!v.IsDefined() || v.IsNull()) fail("missing required key '" + context_ + key + "'");
    try {
        return v.as<T>();
    } catch (const YAML::Exception&) {
        fail(v, "bad value for '" + context_ + key + "': '" + YAML::Dump(v) + "'");
    }
}

template <typename T> std::vector<T> YamlMap::list(const std::string& key, std::size_t max_items) {
    std::vector<T> out;
    const YAML::Node seq = sequence(key, max_items, "values");
    for (std::size_t i = 0; i < seq.size(); ++i) {
        const YAML::Node v = seq[i];
        try {
            if (!v.IsScalar()) throw YAML::BadConversion(v.Mark());
            out.push_back(v.as<T>());
        } catch (const YAML::Exception&) {
            fail(v, "bad value for '" + context_ + key + "[" + std::to_string(i) + "]': '" + YAML::Dump(v) + "'");
        }
    }
    return out;
}

/// The largest configuration file rcsim reads (a scenario is a few kilobytes; this bounds the
/// memory a wrong path such as /dev/zero or a log file given as the scenario can take).
constexpr std::uintmax_t kMaxYamlFileBytes = 4u << 20;

/// Loads a YAML file: a regular file of at most kMaxYamlFileBytes holding one document whose
/// mappings have no key twice. Any other input becomes a ConfigError naming file and line.
YAML::Node load_yaml_file(const std::string& path);

/// Throws ConfigError (at the second occurrence's line) when a mapping in `node`, at any depth,
/// has the same key twice: yaml-cpp keeps both and lookups would silently take the first.
void reject_duplicate_keys(const YAML::Node& node, const std::string& file);

} // namespace rcsim

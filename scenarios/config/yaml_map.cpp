#include "scenarios/config/yaml_map.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_set>

namespace rcsim {

YamlMap::YamlMap(YAML::Node node, std::string file, std::string context)
    : node_(node), file_(std::move(file)), context_(std::move(context)) {
    if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap()) fail(node_, "'" + name() + "' must be a mapping");
}

std::string YamlMap::name() const {
    // context_ is "board." or "ports[0].": the key without its trailing dot.
    return context_.empty() ? std::string("top level") : context_.substr(0, context_.size() - 1);
}

bool YamlMap::has(const std::string& key) const {
    return node_.IsMap() && node_[key].IsDefined() && !node_[key].IsNull();
}

YAML::Node YamlMap::child(const std::string& key) {
    used_.insert(key);
    if (!node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    return node_[key];
}

YamlMap YamlMap::map(const std::string& key) { return YamlMap(child(key), file_, context_ + key + "."); }

double YamlMap::number(const std::string& key, double fallback, double lo, double hi) {
    const double v = get<double>(key, fallback);
    if (!(v >= lo && v <= hi)) {
        std::ostringstream os;
        os << "'" << context_ << key << "' = " << v << " is out of range [" << lo << ", " << hi << "]";
        fail(has(key) ? node_[key] : node_, os.str());
    }
    return v;
}

std::uint64_t YamlMap::integer(const std::string& key, std::uint64_t fallback, std::uint64_t lo, std::uint64_t hi) {
    const double v = get<double>(key, static_cast<double>(fallback));
    if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi)) || v != std::floor(v)) {
        std::ostringstream os;
        os << "'" << context_ << key << "' = " << v << " must be a whole number in [" << lo << ", " << hi << "]";
        fail(has(key) ? node_[key] : node_, os.str());
    }
    return static_cast<std::uint64_t>(v);
}

double YamlMap::require_number(const std::string& key, double lo, double hi) {
    if (!has(key)) fail("missing required key '" + context_ + key + "'");
    return number(key, 0, lo, hi);
}

std::string YamlMap::choice(const std::string& key, const std::string& fallback,
                            std::initializer_list<const char*> allowed) {
    const std::string v = get<std::string>(key, fallback);
    for (const char* a : allowed)
        if (v == a) return v;
    // "'a' or 'b'", "'a', 'b' or 'c'"
    std::string names;
    std::size_t i = 0;
    for (const char* a : allowed) {
        if (i++) names += i == allowed.size() ? " or " : ", ";
        names += std::string("'") + a + "'";
    }
    fail(child(key), "'" + context_ + key + "' must be " + names + ", got '" + v + "'");
}

YAML::Node YamlMap::sequence(const std::string& key, std::size_t max_items, const char* of) {
    if (!has(key)) {
        child(key);
        return YAML::Node(YAML::NodeType::Undefined);
    }
    YAML::Node seq = child(key);
    if (!seq.IsSequence() || seq.size() > max_items) {
        std::string what = "'" + context_ + key + "' must be a list of ";
        if (max_items != std::numeric_limits<std::size_t>::max()) what += "at most " + std::to_string(max_items) + " ";
        fail(seq, what + of);
    }
    return seq;
}

std::vector<YamlMap> YamlMap::maps(const std::string& key, std::size_t max_items) {
    std::vector<YamlMap> out;
    const YAML::Node seq = sequence(key, max_items, "mappings");
    for (std::size_t i = 0; i < seq.size(); ++i)
        out.emplace_back(seq[i], file_, context_ + key + "[" + std::to_string(i) + "].");
    return out;
}

void YamlMap::finish() const {
    if (!node_.IsMap()) return;
    for (const auto& kv : node_) {
        if (!kv.first.IsScalar())
            fail(kv.first, "a key in '" + name() + "' must be a plain name, not '" + YAML::Dump(kv.first) + "'");
        const auto key = kv.first.Scalar();
        if (!used_.count(key)) fail(kv.first, "unknown key '" + context_ + key + "'");
    }
}

void YamlMap::fail(const YAML::Node& at, const std::string& message) const {
    throw ConfigError(file_, line_of(at), message);
}

void reject_duplicate_keys(const YAML::Node& root, const std::string& file) {
    // Iterative, and each container once: an alias (*a) is the node its anchor defined, at the
    // same mark, so a file of aliases to aliases costs no more than its text.
    std::vector<YAML::Node> todo{root};
    std::unordered_set<int> seen;
    while (!todo.empty()) {
        const YAML::Node n = todo.back();
        todo.pop_back();
        if (!n.IsMap() && !n.IsSequence()) continue;
        if (!n.Mark().is_null() && !seen.insert(n.Mark().pos).second) continue;
        if (n.IsSequence()) {
            for (const auto& item : n) todo.push_back(item);
            continue;
        }
        std::map<std::string, int> first_line;
        for (const auto& kv : n) {
            if (kv.first.IsScalar()) {
                const int line = YamlMap::line_of(kv.first);
                const auto [it, fresh] = first_line.emplace(kv.first.Scalar(), line);
                if (!fresh)
                    throw ConfigError(file, line,
                                      "duplicate key '" + kv.first.Scalar() + "' (" +
                                          (it->second == line ? std::string("twice on this line")
                                                              : "first at line " + std::to_string(it->second)) +
                                          ")");
            }
            todo.push_back(kv.second);
        }
    }
}

YAML::Node load_yaml_file(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (fs::is_directory(st)) throw ConfigError(path, 0, "is a directory, not a scenario file");
    if (fs::exists(st) && !fs::is_regular_file(st)) throw ConfigError(path, 0, "is not a regular file");
    std::ifstream in(path);
    if (!in) throw ConfigError(path, 0, "cannot open scenario file");
    const std::uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > kMaxYamlFileBytes)
        throw ConfigError(path, 0, "is " + std::to_string(size) + " bytes; a scenario file is at most " +
                                       std::to_string(kMaxYamlFileBytes) + " bytes");
    std::vector<YAML::Node> docs;
    try {
        docs = YAML::LoadAll(in);
    } catch (const YAML::ParserException& e) {
        throw ConfigError(path, e.mark.line + 1, "YAML syntax error: " + e.msg);
    } catch (const std::ios_base::failure& e) {
        throw ConfigError(path, 0, std::string("cannot read scenario file: ") + e.what());
    }
    if (docs.empty()) return YAML::Node();
    if (docs.size() > 1)
        throw ConfigError(path, YamlMap::line_of(docs[1]),
                          "a second YAML document ('---'): a scenario file is one document");
    reject_duplicate_keys(docs[0], path);
    return docs[0];
}

} // namespace rcsim

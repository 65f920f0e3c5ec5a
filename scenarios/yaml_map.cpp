#include "scenarios/yaml_map.h"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace rcsim {

YamlMap::YamlMap(YAML::Node node, std::string file, std::string context)
    : node_(node), file_(std::move(file)), context_(std::move(context)) {
    if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap()) {
        // context_ is "board." or "ports[0].": name the key without its trailing dot.
        const std::string what = context_.empty() ? std::string("top level") : context_.substr(0, context_.size() - 1);
        fail(node_, "'" + what + "' must be a mapping");
    }
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

void YamlMap::finish() const {
    if (!node_.IsMap()) return;
    for (const auto& kv : node_) {
        if (!kv.first.IsScalar())
            fail(kv.first, "a key in '" + (context_.empty() ? std::string("top level") : context_) +
                               "' must be a plain name, not '" + YAML::Dump(kv.first) + "'");
        const auto key = kv.first.Scalar();
        if (!used_.count(key)) fail(kv.first, "unknown key '" + context_ + key + "'");
    }
}

void YamlMap::fail(const YAML::Node& at, const std::string& message) const {
    throw ConfigError(file_, line_of(at), message);
}

YAML::Node load_yaml_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw ConfigError(path, 0, "is a directory, not a scenario file");
    std::ifstream in(path);
    if (!in) throw ConfigError(path, 0, "cannot open scenario file");
    try {
        return YAML::Load(in);
    } catch (const YAML::ParserException& e) {
        throw ConfigError(path, e.mark.line + 1, "YAML syntax error: " + e.msg);
    } catch (const std::ios_base::failure& e) {
        throw ConfigError(path, 0, std::string("cannot read scenario file: ") + e.what());
    }
}

} // namespace rcsim

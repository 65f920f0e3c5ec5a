// rcsim — the Structured Text parser: the PEGTL grammar (grammar.h) run over a source text, giving
// a parse tree of the rules the compiler reads. Syntax errors throw CompileError with
// "file:line:column: expected X, found Y".
#pragma once

#include <tao/pegtl/contrib/parse_tree.hpp>

#include <memory>
#include <string>

namespace rcsim::st {

using ParseNode = tao::pegtl::parse_tree::node;

/// Parses a whole compilation unit. The returned root keeps pointers into `text`'s copy held by
/// the node's input; `text` and `file` must outlive it.
std::unique_ptr<ParseNode> parse(const std::string& text, const std::string& file);

} // namespace rcsim::st

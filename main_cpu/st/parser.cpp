// rcsim — Structured Text parser. See parser.h.
#include "main_cpu/st/parser.h"

#include "main_cpu/st/grammar.h"
#include "main_cpu/st/types.h"

#include <cctype>
#include <string_view>
#include <type_traits>

namespace rcsim::st {
namespace {

namespace pg = tao::pegtl;
namespace g = grammar;
namespace pt = tao::pegtl::parse_tree;

template <typename R, typename = void> struct has_expected : std::false_type {};
template <typename R> struct has_expected<R, std::void_t<decltype(R::expected)>> : std::true_type {};
template <typename R, typename = void> struct has_unsupported : std::false_type {};
template <typename R> struct has_unsupported<R, std::void_t<decltype(R::unsupported)>> : std::true_type {};

/// What the text holds where the parse failed: a word, a character, or the end.
template <typename Input> std::string found_at(const Input& in) {
    if (in.empty()) return "the end of the file";
    const char* p = in.current();
    const std::size_t n = in.size(64);
    std::size_t len = 0;
    auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '#'; };
    while (len < n && word(p[len])) ++len;
    if (len == 0) {
        // An operator of two characters is shown whole.
        static const char* const pairs[] = {":=", "=>", "<=", ">=", "<>", "**", "..", "(*", "*)"};
        len = 1;
        for (const char* op : pairs)
            if (n >= 2 && p[0] == op[0] && p[1] == op[1]) len = 2;
    }
    if (p[0] == '\n' || p[0] == '\r') return "the end of the line";
    return "'" + std::string(p, len) + "'";
}

/// How deep parentheses, operators and statements may nest: the parser, the compiler and the
/// executor recurse once per level, and a text must not be able to exhaust the stack.
constexpr std::size_t max_nesting = 200;
thread_local std::size_t nesting = 0;

// (Rules the selector keeps: the parse tree calls this control's start/success/failure for those.)
template <typename Rule>
constexpr bool nests = std::is_same_v<Rule, g::paren> || std::is_same_v<Rule, g::negation> ||
                       std::is_same_v<Rule, g::index> || std::is_same_v<Rule, g::call> ||
                       std::is_same_v<Rule, g::if_stmt> || std::is_same_v<Rule, g::case_stmt> ||
                       std::is_same_v<Rule, g::for_stmt> || std::is_same_v<Rule, g::while_stmt> ||
                       std::is_same_v<Rule, g::repeat_stmt> || std::is_same_v<Rule, g::struct_init>;

/// Raises every must<> failure as "expected <what the rule names>, found <text>", a construct
/// outside the subset (grammar::refused) as "<construct> is not supported", and refuses nesting
/// deeper than max_nesting.
template <typename Rule> struct control : pg::normal<Rule> {
    template <typename Input, typename... States> static void start(const Input& in, States&&...) {
        if constexpr (nests<Rule>)
            if (++nesting > max_nesting)
                throw pg::parse_error("nesting deeper than " + std::to_string(max_nesting) + " levels", in);
    }
    template <typename Input, typename... States> static void success(const Input&, States&&...) {
        if constexpr (nests<Rule>) --nesting;
    }
    template <typename Input, typename... States> static void failure(const Input&, States&&...) {
        if constexpr (nests<Rule>) --nesting;
    }
    template <typename Input, typename... States>
    [[noreturn]] static void raise(const Input& in, States&&...) {
        if constexpr (has_unsupported<Rule>::value)
            throw pg::parse_error(std::string(Rule::unsupported) + " is not supported (docs/st.md)", in);
        std::string what = "valid syntax";
        if constexpr (has_expected<Rule>::value) what = Rule::expected;
        throw pg::parse_error("expected " + what + ", found " + found_at(in), in);
    }
};

template <typename Rule>
using selector = pt::selector<
    Rule,
    pt::store_content::on<g::ident, g::int_lit, g::real_lit, g::time_lit, g::bool_lit, g::signed_int, g::op_pow,
                          g::op_neg, g::op_not, g::op_mul, g::op_add, g::op_cmp, g::op_eq, g::op_and, g::op_xor,
                          g::op_or, g::var_kind, g::type_prefix, g::typed_neg, g::enum_value, g::string_lit,
                          g::var_constant, g::typed_lit>,
    pt::remove_content::on<g::paren, g::member, g::index, g::variable, g::arg_input, g::arg_output, g::arguments, g::call,
                           g::negation, g::statements, g::call_stmt, g::assignment, g::else_part, g::elsif_part,
                           g::if_stmt, g::case_range, g::case_labels, g::case_element, g::case_stmt, g::for_by,
                           g::for_stmt, g::while_stmt, g::repeat_stmt, g::exit_stmt, g::return_stmt, g::array_type,
                           g::array_init, g::init, g::names, g::var_decl, g::var_block, g::program,
                           g::function_block, g::function, g::continue_stmt, g::string_type,
                           g::enum_item, g::enum_spec, g::struct_spec, g::type_decl, g::type_block, g::member_init,
                           g::struct_init>,
    pt::fold_one::on<g::power, g::term, g::sum, g::comparison, g::equality, g::conjunction, g::exclusive,
                     g::disjunction>>;

} // namespace

std::unique_ptr<ParseNode> parse(const std::string& text, const std::string& file) {
    // The file name as a view: the nodes keep it (and pointers into `text`) after the input is gone.
    pg::memory_input<pg::tracking_mode::eager, pg::eol::lf_crlf, std::string_view> in(text.data(), text.size(),
                                                                                     std::string_view(file));
    nesting = 0;
    try {
        auto root = pt::parse<g::unit, selector, pg::nothing, control>(in);
        if (!root) throw CompileError(file + ":1:1: expected PROGRAM, FUNCTION_BLOCK, FUNCTION or VAR_GLOBAL");
        return root;
    } catch (const pg::parse_error& e) {
        const auto& p = e.positions().front();
        throw CompileError(std::string(p.source) + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) + ": " +
                           std::string(e.message()));
    }
}

} // namespace rcsim::st

// rcsim — the PEGTL grammar of the Structured Text subset (docs/st.md; IEC 61131-3 3rd ed. §7.3
// for the statements, Table 71 for the operator precedence, §6.3 for literals).
//
// Keywords are case-insensitive, as are identifiers (the compiler folds them). A rule named in a
// must<> carries `expected`, the words of the parse error ("file:line:column: expected ...").
// The parse tree keeps the rules listed in parser.cpp's selector; the compiler reads that tree.
#pragma once

#include <tao/pegtl.hpp>

namespace rcsim::st::grammar {

namespace pg = tao::pegtl;

// ---- white space and comments ----------------------------------------------------------------
struct comment_end : pg::string<'*', ')'> {};
struct comment_body : pg::until<comment_end, pg::any> {
    static constexpr const char* expected = "'*)' closing the comment";
};
struct block_comment : pg::if_must<pg::string<'(', '*'>, comment_body> {};
struct line_comment : pg::seq<pg::two<'/'>, pg::until<pg::eolf>> {};
struct ws : pg::sor<pg::space, block_comment, line_comment> {};
struct _ : pg::star<ws> {};

/// A punctuation token and the white space after it.
template <typename R> struct tok : pg::seq<R, _> {};

// ---- keywords ----------------------------------------------------------------------------------
template <typename Str> struct kw : pg::seq<Str, pg::not_at<pg::identifier_other>, _> {};
#define RCSIM_ST_KW(name, text)                                                                    \
    struct kw_##name : kw<TAO_PEGTL_ISTRING(text)> {                                               \
        static constexpr const char* expected = text;                                              \
    }
RCSIM_ST_KW(program, "PROGRAM");
RCSIM_ST_KW(end_program, "END_PROGRAM");
RCSIM_ST_KW(function_block, "FUNCTION_BLOCK");
RCSIM_ST_KW(end_function_block, "END_FUNCTION_BLOCK");
RCSIM_ST_KW(function, "FUNCTION");
RCSIM_ST_KW(end_function, "END_FUNCTION");
RCSIM_ST_KW(var, "VAR");
RCSIM_ST_KW(var_input, "VAR_INPUT");
RCSIM_ST_KW(var_output, "VAR_OUTPUT");
RCSIM_ST_KW(var_global, "VAR_GLOBAL");
RCSIM_ST_KW(end_var, "END_VAR");
RCSIM_ST_KW(array, "ARRAY");
RCSIM_ST_KW(of, "OF");
RCSIM_ST_KW(if, "IF");
RCSIM_ST_KW(then, "THEN");
RCSIM_ST_KW(elsif, "ELSIF");
RCSIM_ST_KW(else, "ELSE");
RCSIM_ST_KW(end_if, "END_IF");
RCSIM_ST_KW(case, "CASE");
RCSIM_ST_KW(end_case, "END_CASE");
RCSIM_ST_KW(for, "FOR");
RCSIM_ST_KW(to, "TO");
RCSIM_ST_KW(by, "BY");
RCSIM_ST_KW(do, "DO");
RCSIM_ST_KW(end_for, "END_FOR");
RCSIM_ST_KW(while, "WHILE");
RCSIM_ST_KW(end_while, "END_WHILE");
RCSIM_ST_KW(repeat, "REPEAT");
RCSIM_ST_KW(until, "UNTIL");
RCSIM_ST_KW(end_repeat, "END_REPEAT");
RCSIM_ST_KW(exit, "EXIT");
RCSIM_ST_KW(return, "RETURN");
RCSIM_ST_KW(and, "AND");
RCSIM_ST_KW(or, "OR");
RCSIM_ST_KW(xor, "XOR");
RCSIM_ST_KW(not, "NOT");
RCSIM_ST_KW(mod, "MOD");
RCSIM_ST_KW(true, "TRUE");
RCSIM_ST_KW(false, "FALSE");
#undef RCSIM_ST_KW

struct reserved
    : pg::sor<kw_program, kw_end_program, kw_function_block, kw_end_function_block, kw_function, kw_end_function,
              kw_var, kw_var_input, kw_var_output, kw_var_global, kw_end_var, kw_array, kw_of, kw_if, kw_then,
              kw_elsif, kw_else, kw_end_if, kw_case, kw_end_case, kw_for, kw_to, kw_by, kw_do, kw_end_for,
              kw_while, kw_end_while, kw_repeat, kw_until, kw_end_repeat, kw_exit, kw_return, kw_and, kw_or,
              kw_xor, kw_not, kw_mod, kw_true, kw_false> {};

struct ident : pg::seq<pg::not_at<reserved>, pg::identifier> {
    static constexpr const char* expected = "an identifier";
};

// ---- punctuation ---------------------------------------------------------------------------------
#define RCSIM_ST_PUNCT(name, text, ...)                                                            \
    struct name : tok<__VA_ARGS__> {                                                               \
        static constexpr const char* expected = text;                                              \
    }
RCSIM_ST_PUNCT(semi, "';'", pg::one<';'>);
// (The look-ahead comes first: a must<> failure reports the position where the rule began.)
RCSIM_ST_PUNCT(colon, "':'", pg::seq<pg::not_at<pg::string<':', '='>>, pg::one<':'>>);
RCSIM_ST_PUNCT(assign_op, "':='", pg::string<':', '='>);
RCSIM_ST_PUNCT(output_op, "'=>'", pg::string<'=', '>'>);
RCSIM_ST_PUNCT(comma, "','", pg::one<','>);
RCSIM_ST_PUNCT(lparen, "'('", pg::one<'('>);
RCSIM_ST_PUNCT(rparen, "')'", pg::one<')'>);
RCSIM_ST_PUNCT(lbracket, "'['", pg::one<'['>);
RCSIM_ST_PUNCT(rbracket, "']'", pg::one<']'>);
RCSIM_ST_PUNCT(dotdot, "'..'", pg::two<'.'>);
RCSIM_ST_PUNCT(dot, "'.'", pg::seq<pg::not_at<pg::two<'.'>>, pg::one<'.'>>);
#undef RCSIM_ST_PUNCT

// ---- literals (§6.3.2) ---------------------------------------------------------------------------
struct digits : pg::seq<pg::digit, pg::star<pg::opt<pg::one<'_'>>, pg::digit>> {};
struct based_int : pg::seq<pg::sor<pg::string<'1', '6'>, pg::one<'8'>, pg::one<'2'>>, pg::one<'#'>,
                           pg::xdigit, pg::star<pg::opt<pg::one<'_'>>, pg::xdigit>> {};
struct exponent : pg::seq<pg::one<'e', 'E'>, pg::opt<pg::one<'+', '-'>>, digits> {};
struct real_lit : pg::seq<digits, pg::sor<pg::seq<pg::one<'.'>, digits, pg::opt<exponent>>, exponent>,
                          pg::not_at<pg::identifier_other>> {};
struct int_lit : pg::seq<pg::sor<based_int, digits>, pg::not_at<pg::identifier_other>> {};
// T#1h2m3s4ms5us, T#1.5s, TIME#-10ms: units d h m s ms us ns, each at most once, largest first.
struct time_unit : pg::sor<TAO_PEGTL_ISTRING("ms"), TAO_PEGTL_ISTRING("us"), TAO_PEGTL_ISTRING("ns"),
                           pg::one<'d', 'D', 'h', 'H', 'm', 'M', 's', 'S'>> {};
struct time_part : pg::seq<digits, pg::opt<pg::one<'.'>, digits>, time_unit> {};
struct time_value : pg::seq<pg::opt<pg::one<'-'>>, pg::plus<time_part, pg::opt<pg::one<'_'>>>> {
    static constexpr const char* expected = "a duration such as 10ms or 1s500ms";
};
struct time_lit : pg::seq<pg::sor<TAO_PEGTL_ISTRING("TIME#"), TAO_PEGTL_ISTRING("T#")>, pg::must<time_value>,
                          pg::not_at<pg::identifier_other>> {};
struct bool_lit : pg::sor<kw_true, kw_false> {};
struct literal : pg::seq<pg::sor<time_lit, real_lit, int_lit, bool_lit>, _> {};

// ---- expressions (Table 71: highest precedence first) --------------------------------------------
struct expression;
struct expr_expected;
struct member : pg::seq<dot, pg::must<ident>, _> {};
struct index : pg::if_must<lbracket, expr_expected, rbracket> {};
struct variable : pg::seq<ident, _, pg::star<pg::sor<member, index>>> {
    static constexpr const char* expected = "a variable";
};
// A call argument: a named input (Name := value), an output (Name => variable) or a value.
struct arg_input : pg::seq<ident, _, assign_op, pg::must<expr_expected>> {};
struct arg_output : pg::seq<ident, _, output_op, pg::must<variable>> {};
struct argument : pg::sor<arg_input, arg_output, expression> {
    static constexpr const char* expected = "an argument";
};
struct arguments : pg::opt<argument, pg::star<comma, pg::must<argument>>> {};
struct call : pg::seq<ident, _, lparen, arguments, pg::must<rparen>> {};
struct paren : pg::if_must<lparen, expr_expected, rparen> {};
struct primary : pg::sor<paren, literal, call, variable> {
    static constexpr const char* expected = "an operand";
};
struct op_pow : tok<pg::two<'*'>> {};
struct power : pg::seq<primary, pg::star<op_pow, pg::must<primary>>> {};
struct op_neg : tok<pg::one<'-'>> {};
struct op_not : kw_not {};
struct unary;
struct negation : pg::seq<pg::sor<op_neg, op_not>, pg::must<unary>> {};
struct unary : pg::sor<negation, power> {
    static constexpr const char* expected = "an operand";
};
struct op_mul : pg::sor<tok<pg::seq<pg::one<'*'>, pg::not_at<pg::one<'*', ')'>>>>, tok<pg::one<'/'>>, kw_mod> {};
struct term : pg::seq<unary, pg::star<op_mul, pg::must<unary>>> {
    static constexpr const char* expected = "an operand";
};
struct op_add : pg::sor<tok<pg::one<'+'>>, tok<pg::one<'-'>>> {};
struct sum : pg::seq<term, pg::star<op_add, pg::must<term>>> {
    static constexpr const char* expected = "an operand";
};
struct op_cmp : tok<pg::sor<pg::string<'<', '='>, pg::string<'>', '='>, pg::seq<pg::one<'<'>, pg::not_at<pg::one<'>'>>>,
                            pg::one<'>'>>> {};
struct comparison : pg::seq<sum, pg::star<op_cmp, pg::must<sum>>> {
    static constexpr const char* expected = "an operand";
};
struct op_eq : tok<pg::sor<pg::seq<pg::one<'='>, pg::not_at<pg::one<'>'>>>, pg::string<'<', '>'>>> {};
struct equality : pg::seq<comparison, pg::star<op_eq, pg::must<comparison>>> {
    static constexpr const char* expected = "an operand";
};
struct op_and : pg::sor<kw_and, tok<pg::one<'&'>>> {};
struct conjunction : pg::seq<equality, pg::star<op_and, pg::must<equality>>> {
    static constexpr const char* expected = "an operand";
};
struct op_xor : kw_xor {};
struct exclusive : pg::seq<conjunction, pg::star<op_xor, pg::must<conjunction>>> {
    static constexpr const char* expected = "an operand";
};
struct op_or : kw_or {};
struct disjunction : pg::seq<exclusive, pg::star<op_or, pg::must<exclusive>>> {};
// (seq<>, not inheritance: the parse tree names a node by the rule that matched it.)
struct expression : pg::seq<disjunction> {};
struct expr_expected : pg::seq<disjunction> {
    static constexpr const char* expected = "an expression";
};

// ---- statements (§7.3.2) -------------------------------------------------------------------------
struct statement;
/// Where a statement list ends: a closing keyword, a CASE label, or the end of the text.
struct stmt_end
    : pg::sor<kw_end_if, kw_elsif, kw_else, kw_end_case, kw_end_for, kw_end_while, kw_until, kw_end_repeat,
              kw_end_program, kw_end_function_block, kw_end_function, pg::seq<pg::opt<pg::one<'-'>>, pg::digit>,
              pg::eof> {};
struct statements : pg::star<pg::not_at<stmt_end>, pg::must<statement>> {};

struct call_stmt : pg::seq<call, pg::must<semi>> {};
struct assignment : pg::seq<variable, pg::must<assign_op>, pg::must<expr_expected>, pg::must<semi>> {};
struct else_part : pg::if_must<kw_else, statements> {};
struct elsif_part : pg::if_must<kw_elsif, expr_expected, kw_then, statements> {};
struct if_stmt : pg::if_must<kw_if, expr_expected, kw_then, statements, pg::star<elsif_part>, pg::opt<else_part>,
                             kw_end_if, semi> {};
struct signed_int : pg::seq<pg::opt<pg::one<'-'>>, int_lit, _> {
    static constexpr const char* expected = "an integer";
};
struct case_range : pg::seq<signed_int, pg::opt<dotdot, pg::must<signed_int>>> {
    static constexpr const char* expected = "a CASE label";
};
struct case_labels : pg::seq<case_range, pg::star<comma, pg::must<case_range>>> {};
struct case_element : pg::seq<case_labels, pg::must<colon>, statements> {};
struct case_elements : pg::plus<case_element> {
    static constexpr const char* expected = "a CASE label such as 1: or 2..5:";
};
struct case_stmt : pg::if_must<kw_case, expr_expected, kw_of, case_elements, pg::opt<else_part>, kw_end_case,
                               semi> {};
struct for_by : pg::if_must<kw_by, expr_expected> {};
struct for_stmt : pg::if_must<kw_for, ident, _, assign_op, expr_expected, kw_to, expr_expected, pg::opt<for_by>,
                              kw_do, statements, kw_end_for, semi> {};
struct while_stmt : pg::if_must<kw_while, expr_expected, kw_do, statements, kw_end_while, semi> {};
struct repeat_stmt : pg::if_must<kw_repeat, statements, kw_until, expr_expected, kw_end_repeat, semi> {};
struct exit_stmt : pg::if_must<kw_exit, semi> {};
struct return_stmt : pg::if_must<kw_return, semi> {};
struct empty_stmt : semi {};
struct statement : pg::sor<if_stmt, case_stmt, for_stmt, while_stmt, repeat_stmt, exit_stmt, return_stmt, call_stmt,
                           assignment, empty_stmt> {
    static constexpr const char* expected = "a statement";
};

// ---- declarations (§6.5) -------------------------------------------------------------------------
struct type_name : pg::seq<ident, _> {
    static constexpr const char* expected = "a type name";
};
struct array_type : pg::if_must<kw_array, lbracket, signed_int, dotdot, signed_int, rbracket, kw_of, type_name> {};
struct type_spec : pg::sor<array_type, type_name> {
    static constexpr const char* expected = "a type";
};
struct array_init : pg::if_must<lbracket, expr_expected, pg::star<comma, pg::must<expr_expected>>, rbracket> {};
struct initializer : pg::sor<array_init, expression> {
    static constexpr const char* expected = "an initial value";
};
struct init : pg::seq<assign_op, pg::must<initializer>> {};
struct names : pg::seq<ident, _, pg::star<comma, pg::must<ident>, _>> {};
struct var_decl : pg::seq<names, pg::must<colon>, pg::must<type_spec>, pg::opt<init>, pg::must<semi>> {
    static constexpr const char* expected = "a declaration 'name : TYPE;' or END_VAR";
};
struct var_kind : pg::sor<kw_var_input, kw_var_output, kw_var_global, kw_var> {};
struct var_block : pg::if_must<var_kind, pg::star<pg::not_at<kw_end_var>, pg::must<var_decl>>, kw_end_var> {};
struct var_blocks : pg::star<var_block> {};

// ---- program organisation units (§6.6) ------------------------------------------------------------
struct pou_name : pg::seq<ident, _> {
    static constexpr const char* expected = "a name";
};
struct program : pg::if_must<kw_program, pou_name, var_blocks, statements, kw_end_program> {};
struct function_block : pg::if_must<kw_function_block, pou_name, var_blocks, statements, kw_end_function_block> {};
struct function : pg::if_must<kw_function, pou_name, colon, type_name, var_blocks, statements, kw_end_function> {};
struct top_item : pg::sor<program, function_block, function, var_block> {
    static constexpr const char* expected = "PROGRAM, FUNCTION_BLOCK, FUNCTION or VAR_GLOBAL";
};
struct unit : pg::seq<_, pg::until<pg::eof, pg::must<top_item>>> {};

} // namespace rcsim::st::grammar

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

// ---- constructs outside the subset -------------------------------------------------------------
/// A construct of IEC 61131-3 that the subset leaves out: recognised where it starts and refused
/// with "<unsupported> is not supported" (parser.cpp's control) instead of a parse error about
/// whatever token follows it.
template <typename R> struct refused : pg::seq<pg::at<R>, pg::raise<R>> {};
#define RCSIM_ST_REFUSE(name, text, ...)                                                            \
    struct name : __VA_ARGS__ {                                                                    \
        static constexpr const char* unsupported = text;                                           \
    }
template <typename Str> struct word : pg::seq<Str, pg::not_at<pg::identifier_other>> {};
RCSIM_ST_REFUSE(no_pointer, "POINTER TO", word<TAO_PEGTL_ISTRING("POINTER")>);
RCSIM_ST_REFUSE(no_ref_to, "REF_TO", word<TAO_PEGTL_ISTRING("REF_TO")>);
RCSIM_ST_REFUSE(no_reference, "REFERENCE TO", word<TAO_PEGTL_ISTRING("REFERENCE")>);
RCSIM_ST_REFUSE(no_inline_enum, "an enumeration declared in a variable's type (declare it in TYPE ... END_TYPE)",
                pg::one<'('>);
RCSIM_ST_REFUSE(no_inline_struct, "a STRUCT declared in a variable's type (declare it in TYPE ... END_TYPE)",
                word<TAO_PEGTL_ISTRING("STRUCT")>);
RCSIM_ST_REFUSE(no_array_dims, "an ARRAY of more than one dimension", pg::one<','>);
RCSIM_ST_REFUSE(no_var_section, "this variable section (VAR_TEMP, VAR_EXTERNAL, VAR_ACCESS, VAR_CONFIG)",
                word<pg::sor<TAO_PEGTL_ISTRING("VAR_TEMP"), TAO_PEGTL_ISTRING("VAR_EXTERNAL"),
                             TAO_PEGTL_ISTRING("VAR_ACCESS"), TAO_PEGTL_ISTRING("VAR_CONFIG")>>);
RCSIM_ST_REFUSE(no_retain, "RETAIN, NON_RETAIN, PERSISTENT",
                word<pg::sor<TAO_PEGTL_ISTRING("RETAIN"), TAO_PEGTL_ISTRING("NON_RETAIN"),
                             TAO_PEGTL_ISTRING("PERSISTENT")>>);
RCSIM_ST_REFUSE(no_at, "AT (a located variable)", word<TAO_PEGTL_ISTRING("AT")>);
RCSIM_ST_REFUSE(no_config, "CONFIGURATION, RESOURCE, CLASS, INTERFACE, NAMESPACE (one task, no OOP)",
                word<pg::sor<TAO_PEGTL_ISTRING("CONFIGURATION"), TAO_PEGTL_ISTRING("RESOURCE"),
                             TAO_PEGTL_ISTRING("CLASS"), TAO_PEGTL_ISTRING("INTERFACE"),
                             TAO_PEGTL_ISTRING("NAMESPACE")>>);
RCSIM_ST_REFUSE(no_oop, "EXTENDS, IMPLEMENTS (the OOP extensions)",
                word<pg::sor<TAO_PEGTL_ISTRING("EXTENDS"), TAO_PEGTL_ISTRING("IMPLEMENTS")>>);
// (In a statement list, a word followed by a name: a variable may be called Action.)
RCSIM_ST_REFUSE(no_oop_body, "METHOD, PROPERTY, ACTION (the OOP extensions)",
                pg::seq<word<pg::sor<TAO_PEGTL_ISTRING("METHOD"), TAO_PEGTL_ISTRING("PROPERTY"),
                                     TAO_PEGTL_ISTRING("ACTION")>>,
                        pg::plus<pg::blank>, pg::identifier>);
RCSIM_ST_REFUSE(no_jump, "JMP (jumps and labels)", pg::seq<word<TAO_PEGTL_ISTRING("JMP")>, pg::plus<pg::blank>, pg::identifier>);
RCSIM_ST_REFUSE(no_pragma, "a pragma { }", pg::one<'{'>);
RCSIM_ST_REFUSE(no_subrange, "a subrange type such as INT(0..100)", pg::one<'('>);
RCSIM_ST_REFUSE(no_set_reset, "S=, R=, REF= (set, reset and reference assignments)",
                pg::sor<pg::seq<pg::one<'S', 's', 'R', 'r'>, pg::one<'='>>, pg::seq<TAO_PEGTL_ISTRING("REF"), pg::one<'='>>>);
RCSIM_ST_REFUSE(no_deref, "the dereference '^'", pg::one<'^'>);
RCSIM_ST_REFUSE(no_date_lit, "a DATE, TIME_OF_DAY, DATE_AND_TIME or LTIME literal",
                pg::sor<TAO_PEGTL_ISTRING("DATE_AND_TIME#"), TAO_PEGTL_ISTRING("TIME_OF_DAY#"),
                        TAO_PEGTL_ISTRING("DATE#"), TAO_PEGTL_ISTRING("TOD#"), TAO_PEGTL_ISTRING("DT#"),
                        TAO_PEGTL_ISTRING("D#"), TAO_PEGTL_ISTRING("LTIME#"), TAO_PEGTL_ISTRING("LT#")>);
RCSIM_ST_REFUSE(no_wstring_lit, "a WSTRING literal \"...\"", pg::one<'"'>);
#undef RCSIM_ST_REFUSE

// ---- white space and comments ----------------------------------------------------------------
/// The rest of a comment after its "(*", up to the matching "*)": comments nest (IEC 61131-3
/// 3rd ed. Table 1, feature 5: "(* (* NESTED *) *)"). A counter, not a recursive rule, so any
/// depth costs no stack.
struct comment_body {
    using rule_t = comment_body;
    using subs_t = pg::empty_list;
    static constexpr const char* expected = "'*)' closing the comment";
    template <typename Input> static bool match(Input& in) {
        std::size_t depth = 1;
        while (!in.empty()) {
            const char* p = in.current();
            const bool two = in.size(2) >= 2;
            if (two && p[0] == '(' && p[1] == '*') {
                ++depth;
                in.bump(2);
            } else if (two && p[0] == '*' && p[1] == ')') {
                in.bump(2);
                if (--depth == 0) return true;
            } else {
                in.bump(1);
            }
        }
        return false;
    }
};
struct block_comment : pg::if_must<pg::string<'(', '*'>, comment_body> {};
struct line_comment : pg::seq<pg::two<'/'>, pg::until<pg::eolf>> {};
struct ws : pg::sor<pg::space, block_comment, line_comment, refused<no_pragma>> {};
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
RCSIM_ST_KW(var_in_out, "VAR_IN_OUT");
RCSIM_ST_KW(constant, "CONSTANT");
RCSIM_ST_KW(type, "TYPE");
RCSIM_ST_KW(end_type, "END_TYPE");
RCSIM_ST_KW(struct, "STRUCT");
RCSIM_ST_KW(end_struct, "END_STRUCT");
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
RCSIM_ST_KW(continue, "CONTINUE");
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
              kw_var, kw_var_input, kw_var_output, kw_var_global, kw_var_in_out, kw_constant, kw_type, kw_end_type,
              kw_struct, kw_end_struct, kw_end_var, kw_array, kw_of, kw_if, kw_then,
              kw_elsif, kw_else, kw_end_if, kw_case, kw_end_case, kw_for, kw_to, kw_by, kw_do, kw_end_for,
              kw_while, kw_end_while, kw_repeat, kw_until, kw_end_repeat, kw_exit, kw_continue, kw_return, kw_and, kw_or,
              kw_xor, kw_not, kw_mod, kw_true, kw_false> {};

struct ident : pg::seq<pg::not_at<reserved>, pg::identifier> {
    static constexpr const char* expected = "an identifier";
};
struct ident_word : pg::seq<pg::not_at<reserved>, pg::identifier> {};

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
// 'text' with IEC's $ escapes ($$ $' $L $N $P $R $T $hh), §6.3.3 Table 6.
struct string_char : pg::sor<pg::seq<pg::one<'$'>, pg::must<pg::sor<pg::seq<pg::xdigit, pg::xdigit>, pg::one<'$', '\'', 'L', 'l', 'N', 'n', 'P', 'p', 'R', 'r', 'T', 't'>>>>,
                             pg::not_one<'\'', '$', '\n', '\r'>> {};
struct string_lit : pg::if_must<pg::one<'\''>, pg::star<string_char>, pg::one<'\''>> {};
// A typed literal (§6.3.2): INT#5, WORD#16#FF, REAL#1.5, BOOL#TRUE, INT#-5, and Color#Red for a
// value of an enumeration (§6.4.4.2).
struct type_prefix : pg::identifier {};
struct typed_neg : pg::one<'-'> {};
struct enum_value : ident_word {};
struct typed_value : pg::sor<pg::seq<pg::opt<typed_neg>, pg::sor<real_lit, int_lit>>, bool_lit, enum_value> {
    static constexpr const char* expected = "a value such as 5, 16#FF, TRUE or an enumeration value";
};
struct typed_lit : pg::seq<type_prefix, pg::one<'#'>, pg::must<typed_value>> {};
struct literal : pg::seq<pg::sor<time_lit, refused<no_date_lit>, typed_lit, real_lit, int_lit, bool_lit, string_lit,
                                 refused<no_wstring_lit>>,
                         _> {};

// ---- expressions (Table 71: highest precedence first) --------------------------------------------
struct expression;
struct expr_expected;
struct member : pg::seq<dot, pg::must<ident>, _> {};
struct index : pg::if_must<lbracket, expr_expected, rbracket> {};
struct variable : pg::seq<ident, _, pg::star<pg::sor<member, index, refused<no_deref>>>> {
    static constexpr const char* expected = "a variable";
};
// A call argument: a named input (Name := value), an output (Name => variable) or a value.
struct arg_input : pg::seq<ident, _, assign_op, pg::must<expr_expected>> {};
struct arg_output : pg::seq<ident, _, output_op, pg::must<variable>> {};
struct argument : pg::sor<arg_input, arg_output, expression> {
    static constexpr const char* expected = "an argument";
};
struct arguments : pg::opt<argument, pg::star<comma, pg::must<argument>>> {};
// `t[i](...)` calls an element of an ARRAY OF a function block (a statement only).
struct call : pg::seq<ident, _, pg::opt<index>, lparen, arguments, pg::must<rparen>> {};
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
/// A CASE label that is a name (an enumeration value or a constant) or a typed literal: a
/// statement never starts with a name followed by ':', ',' or '..'.
struct named_label_ahead : pg::seq<pg::sor<typed_lit, ident_word>, _, pg::sor<colon, comma, dotdot>> {};
/// Where a statement list ends: a closing keyword, a CASE label, or the end of the text.
struct stmt_end
    : pg::sor<kw_end_if, kw_elsif, kw_else, kw_end_case, kw_end_for, kw_end_while, kw_until, kw_end_repeat,
              kw_end_program, kw_end_function_block, kw_end_function, pg::seq<pg::opt<pg::one<'-'>>, pg::digit>,
              named_label_ahead, pg::eof> {};
struct statements : pg::star<pg::not_at<stmt_end>, pg::must<statement>> {};

struct call_stmt : pg::seq<call, pg::must<semi>> {};
struct assignment : pg::seq<variable, pg::opt<refused<no_set_reset>>, pg::must<assign_op>, pg::must<expr_expected>,
                            pg::must<semi>> {};
struct else_part : pg::if_must<kw_else, statements> {};
struct elsif_part : pg::if_must<kw_elsif, expr_expected, kw_then, statements> {};
struct if_stmt : pg::if_must<kw_if, expr_expected, kw_then, statements, pg::star<elsif_part>, pg::opt<else_part>,
                             kw_end_if, semi> {};
struct signed_int : pg::seq<pg::opt<pg::one<'-'>>, int_lit, _> {
    static constexpr const char* expected = "an integer";
};
struct case_typed : pg::seq<typed_lit, _> {};
struct case_name : pg::seq<ident, _> {};
struct case_value : pg::sor<signed_int, case_typed, case_name> {
    static constexpr const char* expected = "a CASE label";
};
struct case_range : pg::seq<case_value, pg::opt<dotdot, pg::must<case_value>>> {
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
struct continue_stmt : pg::if_must<kw_continue, semi> {};
struct return_stmt : pg::if_must<kw_return, semi> {};
struct empty_stmt : semi {};
struct statement : pg::sor<if_stmt, case_stmt, for_stmt, while_stmt, repeat_stmt, exit_stmt, continue_stmt,
                           return_stmt, refused<no_jump>, refused<no_oop_body>, call_stmt, assignment, empty_stmt> {
    static constexpr const char* expected = "a statement";
};

// ---- declarations (§6.5) -------------------------------------------------------------------------
struct type_name : pg::seq<ident, _> {
    static constexpr const char* expected = "a type name";
};
struct array_close : pg::sor<rbracket, refused<no_array_dims>> {
    static constexpr const char* expected = "']'";
};
struct array_type : pg::if_must<kw_array, lbracket, signed_int, dotdot, signed_int, array_close, kw_of, type_name> {};
// STRING or STRING[n] (§6.4.2: n characters at most; 80 without).
struct string_type : pg::seq<word<TAO_PEGTL_ISTRING("STRING")>, _, pg::opt<lbracket, pg::must<signed_int>, pg::must<rbracket>>> {};
struct type_spec : pg::sor<array_type, string_type, refused<no_pointer>, refused<no_ref_to>, refused<no_reference>,
                           refused<no_inline_enum>, refused<no_inline_struct>,
                           pg::seq<type_name, pg::opt<refused<no_subrange>>>> {
    static constexpr const char* expected = "a type";
};
struct initializer;
// [1, 2, 3] or [(x := 1), (x := 2)]: an element may itself be a list or a STRUCT's initial value.
struct array_init : pg::if_must<lbracket, initializer, pg::star<comma, pg::must<initializer>>, rbracket> {};
// (x := 1, y := 2): a STRUCT's initial value by member (§6.4.4.4).
struct member_init : pg::seq<ident, _, pg::must<assign_op>, pg::must<initializer>> {
    static constexpr const char* expected = "a member's initial value 'name := value'";
};
// (A look-ahead as not_at<not_at<>>: the parse tree keeps the nodes an at<> matched.)
struct struct_init : pg::seq<pg::not_at<pg::not_at<lparen, ident, _, assign_op>>, lparen, member_init,
                             pg::star<comma, pg::must<member_init>>, pg::must<rparen>> {};
struct initializer : pg::sor<array_init, struct_init, expression> {
    static constexpr const char* expected = "an initial value";
};
struct init : pg::seq<assign_op, pg::must<initializer>> {};
struct names : pg::seq<ident, _, pg::star<comma, pg::must<ident>, _>> {};
struct var_decl : pg::seq<names, pg::opt<refused<no_at>>, pg::must<colon>, pg::must<type_spec>, pg::opt<init>,
                          pg::must<semi>> {
    static constexpr const char* expected = "a declaration 'name : TYPE;' or END_VAR";
};
struct var_kind : pg::sor<kw_var_input, kw_var_output, kw_var_in_out, kw_var_global, refused<no_var_section>, kw_var> {};
struct var_constant : kw_constant {};
struct var_block : pg::if_must<var_kind, pg::opt<pg::sor<var_constant, refused<no_retain>>>,
                               pg::star<pg::not_at<kw_end_var>, pg::must<var_decl>>, kw_end_var> {};
// ---- data type declarations (§6.4.4): TYPE ... END_TYPE ----------------------------------------------
struct enum_item : pg::seq<ident, _, pg::opt<assign_op, pg::must<signed_int>>> {
    static constexpr const char* expected = "an enumeration value";
};
struct enum_spec : pg::if_must<lparen, enum_item, pg::star<comma, pg::must<enum_item>>, rparen> {};
struct struct_spec : pg::if_must<kw_struct, pg::star<pg::not_at<kw_end_struct>, pg::must<var_decl>>, kw_end_struct> {};
struct type_def : pg::sor<enum_spec, struct_spec, type_spec> {
    static constexpr const char* expected = "an enumeration (A, B, C), a STRUCT or a type";
};
struct type_decl : pg::seq<ident, _, pg::must<colon>, pg::must<type_def>, pg::opt<init>, pg::must<semi>> {
    static constexpr const char* expected = "a type declaration 'Name : ...;' or END_TYPE";
};
struct type_block : pg::if_must<kw_type, pg::star<pg::not_at<kw_end_type>, pg::must<type_decl>>, kw_end_type> {};
struct var_blocks : pg::star<var_block> {};

// ---- program organisation units (§6.6) ------------------------------------------------------------
struct pou_name : pg::seq<ident, _> {
    static constexpr const char* expected = "a name";
};
struct program : pg::if_must<kw_program, pou_name, var_blocks, statements, kw_end_program> {};
struct function_block : pg::if_must<kw_function_block, pou_name, pg::opt<refused<no_oop>>, var_blocks, statements,
                                    kw_end_function_block> {};
struct function : pg::if_must<kw_function, pou_name, colon, type_name, var_blocks, statements, kw_end_function> {};
struct top_item : pg::sor<program, function_block, function, var_block, type_block, refused<no_config>> {
    static constexpr const char* expected = "PROGRAM, FUNCTION_BLOCK, FUNCTION, TYPE or VAR_GLOBAL";
};
struct unit : pg::seq<_, pg::until<pg::eof, pg::must<top_item>>> {};

} // namespace rcsim::st::grammar

// A cursor over the whole text of a mesh file (OBJ, ASCII PLY, ASCII STL): skips blanks, counts
// lines for messages, and reads numbers with std::from_chars (no locale, no allocation). The
// parsers in host/scene_*.cpp consume it; errors are theirs to raise, with cursor.line.
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <system_error>

namespace clvis::detail {

struct TextCursor {
    const char* p;
    const char* end;
    std::size_t line = 1; ///< 1-based line of p

    explicit TextCursor(std::string_view text) : p(text.data()), end(text.data() + text.size()) {}

    bool at_end() const { return p == end; }

    /// A backslash right before the end of a line joins it with the next (OBJ line continuation).
    bool at_continuation() const
    {
        if (p == end || *p != '\\') return false;
        const char* q = p + 1;
        if (q != end && *q == '\r') ++q;
        return q == end || *q == '\n';
    }

    /// Skips spaces and tabs (and OBJ-style continuations when `continuations`), not newlines.
    void skip_blanks(bool continuations = false)
    {
        for (;;) {
            while (p != end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\f' || *p == '\v')) ++p;
            if (!continuations || !at_continuation()) return;
            ++p;
            if (p != end && *p == '\r') ++p;
            if (p != end) { ++p; ++line; }
        }
    }

    /// Skips every kind of white space, newlines included (PLY and STL are token streams).
    void skip_space()
    {
        while (p != end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n' || *p == '\f' || *p == '\v')) {
            if (*p == '\n') ++line;
            ++p;
        }
    }

    /// True at the end of a line: a newline, the end of the text, or a '#' comment.
    bool at_line_end() const { return p == end || *p == '\n' || *p == '#'; }

    /// Moves past the next newline (honouring continuations when asked).
    void next_line(bool continuations = false)
    {
        while (p != end && *p != '\n') {
            if (continuations && at_continuation()) {
                skip_blanks(true);
                continue;
            }
            ++p;
        }
        if (p != end) { ++p; ++line; }
    }

    /// The run of characters up to the next blank, newline or end.
    std::string_view token()
    {
        const char* b = p;
        while (p != end && !is_blank(*p)) ++p;
        return std::string_view(b, std::size_t(p - b));
    }

    static bool is_blank(char c)
    {
        return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
    }
};

/// Where a number at c.p starts: past an optional leading '+', or nullptr for "++" and "+-"
/// (which from_chars would read as a signed number after the '+').
inline const char* number_start(const TextCursor& c)
{
    const char* b = c.p;
    if (b != c.end && *b == '+') {
        ++b;
        if (b != c.end && (*b == '+' || *b == '-')) return nullptr;
    }
    return b;
}

/// Accepts a number read up to `q` when it ends at a blank, a newline, the end, or one of
/// `stops`: moves c.p to `q` and returns true; otherwise leaves c.p and returns false.
inline bool end_number(TextCursor& c, const char* q, std::string_view stops)
{
    if (q != c.end && !TextCursor::is_blank(*q) && stops.find(*q) == std::string_view::npos) return false;
    c.p = q;
    return true;
}

/// Reads a float at c.p (optional leading '+', decimal or scientific, "inf"/"nan" accepted here
/// and refused by the caller as non-finite). The number must end at a blank, a newline, the end,
/// or one of `stops`. Returns false, with c.p unchanged, on anything else.
inline bool parse_float(TextCursor& c, float& out, std::string_view stops = {})
{
    const char* b = number_start(c);
    if (!b) return false;
    auto [q, ec] = std::from_chars(b, c.end, out, std::chars_format::general);
    if (ec == std::errc::result_out_of_range) {
        // From_chars leaves out unchanged: overflow reads as infinity, underflow as zero, so the
        // caller names an overflow as non-finite and a subnormal stays harmless.
        double d = 0;
        auto r = std::from_chars(b, c.end, d, std::chars_format::general);
        if (r.ec != std::errc()) return false;
        out = float(d);
        q = r.ptr;
    } else if (ec != std::errc()) {
        return false;
    }
    return end_number(c, q, stops);
}

/// Reads a double like parse_float reads a float (for PLY's double properties).
inline bool parse_double(TextCursor& c, double& out, std::string_view stops = {})
{
    const char* b = number_start(c);
    if (!b) return false;
    auto [q, ec] = std::from_chars(b, c.end, out, std::chars_format::general);
    if (ec != std::errc()) return false;
    return end_number(c, q, stops);
}

/// Reads a decimal integer (optional sign) that ends like a number of parse_float.
inline bool parse_int(TextCursor& c, std::int64_t& out, std::string_view stops = {})
{
    const char* b = number_start(c);
    if (!b) return false;
    auto [q, ec] = std::from_chars(b, c.end, out);
    if (ec != std::errc()) return false;
    return end_number(c, q, stops);
}

/// The text at c.p for a message: up to the end of its token, at most 32 characters.
inline std::string_view token_preview(const TextCursor& c)
{
    const char* q = c.p;
    while (q != c.end && !TextCursor::is_blank(*q) && q - c.p < 32) ++q;
    return std::string_view(c.p, std::size_t(q - c.p));
}

} // namespace clvis::detail

#pragma once
// A small XML well-formedness check for the tests of generated documents (SVG charts), so that
// they need no XML library: declaration, comments and processing instructions, elements with
// quoted attributes (no duplicates, no '<' in values), entity references, one root element, every
// element closed in order, only whitespace outside the root. DOCTYPE and CDATA are not supported
// (reported as errors): the writers under test never produce them. Plus small accessors to find
// the elements and attribute values a test expects (no <regex>: GCC 12 warns inside it under the
// sanitizers).
#include <cctype>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace thicket::test {

namespace xml_detail {

inline bool name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == ':'; }
inline bool name_char(char c) {
    return name_start(c) || std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '.';
}
inline bool space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// Checks the entity references in character data or an attribute value; "" when they are fine.
inline std::string check_entities(std::string_view s, size_t offset) {
    for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] != '&') continue;
        const size_t semi = s.find(';', i);
        const std::string_view ref = s.substr(i + 1, semi == std::string_view::npos ? 0 : semi - i - 1);
        bool ok = ref == "amp" || ref == "lt" || ref == "gt" || ref == "quot" || ref == "apos";
        if (!ok && ref.size() >= 2 && ref[0] == '#') {
            const bool hex = ref[1] == 'x';
            ok = ref.size() > (hex ? 2u : 1u);
            for (size_t k = hex ? 2 : 1; k < ref.size(); ++k)
                ok = ok && (hex ? std::isxdigit(static_cast<unsigned char>(ref[k]))
                                : std::isdigit(static_cast<unsigned char>(ref[k])));
        }
        if (semi == std::string_view::npos || !ok)
            return "bad entity reference at byte " + std::to_string(offset + i);
    }
    return "";
}

}  // namespace xml_detail

/// "" when `doc` is well-formed by the rules above, else what is wrong and at which byte.
inline std::string xml_wellformedness_error(std::string_view doc) {
    using namespace xml_detail;
    size_t pos = 0;
    const size_t n = doc.size();
    std::vector<std::string> open;
    bool root_seen = false;
    auto at = [&](size_t p) { return " at byte " + std::to_string(p); };
    auto name_at = [&](size_t& p) {
        const size_t start = p;
        if (p >= n || !name_start(doc[p])) return std::string();
        while (p < n && name_char(doc[p])) ++p;
        return std::string(doc.substr(start, p - start));
    };
    while (pos < n) {
        if (doc[pos] != '<') {
            const size_t end = std::min(doc.find('<', pos), n);
            const std::string_view text = doc.substr(pos, end - pos);
            if (open.empty()) {
                for (char c : text)
                    if (!space(c)) return "text outside the root element" + at(pos);
            } else if (std::string e = check_entities(text, pos); !e.empty()) {
                return e;
            }
            pos = end;
            continue;
        }
        const std::string_view rest = doc.substr(pos);
        if (rest.starts_with("<!--")) {
            const size_t end = doc.find("-->", pos + 4);
            if (end == std::string_view::npos) return "unterminated comment" + at(pos);
            pos = end + 3;
        } else if (rest.starts_with("<?")) {
            const bool declaration = rest.starts_with("<?xml") && rest.size() > 5 && space(rest[5]);
            if (declaration && pos != 0) return "XML declaration not at the start" + at(pos);
            const size_t end = doc.find("?>", pos + 2);
            if (end == std::string_view::npos) return "unterminated processing instruction" + at(pos);
            pos = end + 2;
        } else if (rest.starts_with("<!")) {
            return "DOCTYPE and CDATA are not supported" + at(pos);
        } else if (rest.starts_with("</")) {
            size_t p = pos + 2;
            const std::string name = name_at(p);
            while (p < n && space(doc[p])) ++p;
            if (name.empty() || p >= n || doc[p] != '>') return "malformed end tag" + at(pos);
            if (open.empty() || open.back() != name)
                return "end tag </" + name + "> does not close " + (open.empty() ? "anything" : "<" + open.back() + ">") +
                       at(pos);
            open.pop_back();
            pos = p + 1;
        } else {
            size_t p = pos + 1;
            const std::string name = name_at(p);
            if (name.empty()) return "malformed start tag" + at(pos);
            if (open.empty() && root_seen) return "a second root element <" + name + ">" + at(pos);
            std::set<std::string> attributes;
            while (true) {
                const size_t before = p;
                while (p < n && space(doc[p])) ++p;
                if (p >= n) return "unterminated tag <" + name + ">" + at(pos);
                if (doc[p] == '>' || doc.substr(p).starts_with("/>")) break;
                if (p == before) return "attributes of <" + name + "> must be separated by whitespace" + at(p);
                const size_t attr_at = p;
                const std::string attr = name_at(p);
                if (attr.empty()) return "malformed attribute in <" + name + ">" + at(attr_at);
                if (!attributes.insert(attr).second) return "duplicate attribute " + attr + at(attr_at);
                while (p < n && space(doc[p])) ++p;
                if (p >= n || doc[p] != '=') return "attribute " + attr + " has no value" + at(attr_at);
                ++p;
                while (p < n && space(doc[p])) ++p;
                if (p >= n || (doc[p] != '"' && doc[p] != '\'')) return "unquoted value of " + attr + at(attr_at);
                const size_t close = doc.find(doc[p], p + 1);
                if (close == std::string_view::npos) return "unterminated value of " + attr + at(attr_at);
                const std::string_view value = doc.substr(p + 1, close - p - 1);
                if (value.find('<') != std::string_view::npos) return "'<' in the value of " + attr + at(attr_at);
                if (std::string e = check_entities(value, p + 1); !e.empty()) return e;
                p = close + 1;
            }
            root_seen = true;
            if (doc[p] == '>') {
                open.push_back(name);
                pos = p + 1;
            } else {
                pos = p + 2;  // "/>": an empty element
            }
        }
    }
    if (!open.empty()) return "element <" + open.back() + "> is never closed";
    if (!root_seen) return "no root element";
    return "";
}

/// The start tags <element ...> of `doc` in document order, each from '<' to its '>'.
inline std::vector<std::string> start_tags(std::string_view doc, std::string_view element) {
    std::vector<std::string> out;
    std::string open = "<";
    open += element;
    for (size_t p = doc.find(open); p != std::string_view::npos; p = doc.find(open, p + 1)) {
        const size_t after = p + open.size();
        if (after >= doc.size() || !(xml_detail::space(doc[after]) || doc[after] == '>' || doc[after] == '/')) continue;
        const size_t end = doc.find('>', after);
        if (end == std::string_view::npos) break;
        out.emplace_back(doc.substr(p, end - p + 1));
    }
    return out;
}

/// The value of `attribute` in one start tag, as written (entities not decoded), or none.
inline std::optional<std::string> attribute_of(std::string_view tag, std::string_view attribute) {
    std::string key = " ";  // built in steps: GCC 12 warns falsely about "literal" + std::string
    key += attribute;
    key += "=\"";
    const size_t p = tag.find(key);
    if (p == std::string_view::npos) return std::nullopt;
    const size_t begin = p + key.size(), end = tag.find('"', begin);
    if (end == std::string_view::npos) return std::nullopt;
    return std::string(tag.substr(begin, end - begin));
}

/// The values of `attribute` on every <element> that has it, in document order.
inline std::vector<std::string> attribute_values(std::string_view doc, std::string_view element,
                                                 std::string_view attribute) {
    std::vector<std::string> out;
    for (const std::string& tag : start_tags(doc, element))
        if (auto v = attribute_of(tag, attribute)) out.push_back(*v);
    return out;
}

}  // namespace thicket::test

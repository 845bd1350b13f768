// Tables of numbers as text, in one call: a batch's assembly.txt, assembly.vtk and contacts.csv (Python's
// formatting of their 10^6 numbers took most of the batch's last second).
#include "mss/io.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mss {

void appendNumber(std::string& out, double v, NumberText style) {
    if (std::isnan(v)) { // as Python writes either sign's
        out += "nan";
        return;
    }
    if (std::isinf(v)) {
        out += v < 0 ? "-inf" : "inf";
        return;
    }
    std::array<char, 48> buf{};
    if (style == NumberText::Precision17) { // printf's "%.17g", to the character
        const std::to_chars_result r =
            std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::general, 17);
        out.append(buf.data(), r.ptr);
        return;
    }
    if (v == 0) {
        out += std::signbit(v) ? "-0.0" : "0.0";
        return;
    }
    // Python's repr (its float_repr_style 'short'): the shortest digits that read back the same, as to_chars
    // gives them ("d.ddde+XX"), then its layout: a decimal point position decpt (value = 0.DIGITS x 10^decpt)
    // of -3 .. 16 in fixed notation ("0.0001", "100.0"), else d.ddd e+XX with two exponent digits at least
    const std::to_chars_result r =
        std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::scientific);
    const char* p = buf.data();
    if (*p == '-') {
        out.push_back('-');
        ++p;
    }
    std::array<char, 24> digits{};
    std::size_t n = 0;
    for (; p < r.ptr && *p != 'e'; ++p)
        if (*p != '.') digits[n++] = *p;
    int exponent = 0;
    std::from_chars(p + 1 + (p[1] == '+'), r.ptr, exponent);
    const int decpt = exponent + 1;
    if (decpt <= -4 || decpt > 16) {
        out.push_back(digits[0]);
        if (n > 1) {
            out.push_back('.');
            out.append(digits.data() + 1, n - 1);
        }
        out.append(exponent < 0 ? "e-" : "e+");
        const int e = std::abs(exponent);
        if (e < 10) out.push_back('0');
        out += std::to_string(e);
    } else if (decpt <= 0) {
        out += "0.";
        out.append(std::size_t(-decpt), '0');
        out.append(digits.data(), n);
    } else if (std::size_t(decpt) < n) {
        out.append(digits.data(), std::size_t(decpt));
        out.push_back('.');
        out.append(digits.data() + decpt, n - std::size_t(decpt));
    } else {
        out.append(digits.data(), n);
        out.append(std::size_t(decpt) - n, '0');
        out += ".0";
    }
}

namespace {

void appendInteger(std::string& out, std::int64_t v) {
    std::array<char, 24> buf{};
    const std::to_chars_result r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    out.append(buf.data(), r.ptr);
}

} // namespace

std::string formatRows(const std::int64_t* ints, std::size_t intCols, const double* values, std::size_t cols,
                       std::size_t rows, NumberText style, char sep, const std::string& end) {
    if ((intCols > 0 && ints == nullptr) || (cols > 0 && values == nullptr))
        throw std::invalid_argument("formatRows: no numbers given for the columns asked");
    std::string out;
    out.reserve(rows * (intCols * 8 + cols * 24 + end.size()));
    for (std::size_t i = 0; i < rows; ++i) {
        for (std::size_t c = 0; c < intCols; ++c) {
            if (c > 0) out.push_back(sep);
            appendInteger(out, ints[i * intCols + c]);
        }
        for (std::size_t c = 0; c < cols; ++c) {
            if (c > 0 || intCols > 0) out.push_back(sep);
            appendNumber(out, values[i * cols + c], style);
        }
        out += end;
    }
    return out;
}

std::string formatClumpAssembly(const double* spheres, std::size_t count, const std::int64_t* offsets,
                                const std::int64_t* ids, const double* heads, std::size_t clumps) {
    if (clumps > 0 && (offsets == nullptr || ids == nullptr || heads == nullptr))
        throw std::invalid_argument("formatClumpAssembly: no offsets, ids or mass rows for the clumps");
    for (std::size_t c = 0; c < clumps; ++c) // every clump's spheres within those given, in order
        if (offsets[c] < 0 || offsets[c + 1] < offsets[c] || std::size_t(offsets[c + 1]) > count)
            throw std::invalid_argument("formatClumpAssembly: clump " + std::to_string(c) + "'s spheres " +
                                        std::to_string(offsets[c]) + " .. " + std::to_string(offsets[c + 1]) +
                                        " are not within the " + std::to_string(count) + " given, in order");
    static const char* const kWords[10] = {" mass ", " centroid ", " ", " ", " inertia ",
                                           " ",      " ",          " ", " ", " "};
    std::string out;
    out.reserve(std::size_t(clumps > 0 ? offsets[clumps] - offsets[0] : 0) * 100 + clumps * 260);
    for (std::size_t c = 0; c < clumps; ++c) {
        out += "#mss clump ";
        appendInteger(out, ids[c]);
        out += " density 1";
        for (std::size_t k = 0; k < 10; ++k) {
            out += kWords[k];
            appendNumber(out, heads[10 * c + k], NumberText::Shortest);
        }
        out.push_back('\n');
        for (std::int64_t s = offsets[c]; s < offsets[c + 1]; ++s) {
            for (std::size_t k = 0; k < 4; ++k) {
                appendNumber(out, spheres[4 * std::size_t(s) + k], NumberText::Shortest);
                out.push_back(' ');
            }
            appendInteger(out, ids[c]);
            out.push_back('\n');
        }
    }
    return out;
}

} // namespace mss

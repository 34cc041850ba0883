#include "testing/ascii_image.h"

#include <algorithm>
#include <stdexcept>

namespace depthcull::test {

Image ascii_image(const std::vector<std::string>& rows) {
    Image image;
    image.height = int(rows.size());
    for (const auto& row : rows) image.width = std::max(image.width, int(row.size()));
    image.rgba.assign(std::size_t(image.width) * image.height * 4, 0);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < int(rows[y].size()); ++x) {
            char c = rows[y][x];
            std::uint8_t a = 0;
            if (c == '#') a = 255;
            else if (c == '+') a = 128;
            else if (c >= '1' && c <= '9') a = std::uint8_t((c - '0') * 25);
            else if (c != '.' && c != ' ') throw std::invalid_argument(std::string("ascii_image: bad character ") + c);
            std::uint8_t* t = &image.rgba[(std::size_t(y) * image.width + x) * 4];
            // Colour varies with position so render tests see texel mix-ups.
            t[0] = std::uint8_t(x * 37 + 11);
            t[1] = std::uint8_t(y * 53 + 7);
            t[2] = std::uint8_t((x ^ y) * 29 + 3);
            t[3] = a;
        }
    }
    return image;
}

std::vector<std::string> ascii_rows(ImageView image) {
    std::vector<std::string> rows;
    for (int y = 0; y < image.height; ++y) {
        std::string row;
        for (int x = 0; x < image.width; ++x) {
            std::uint8_t a = image.alpha(x, y);
            row += a == 0 ? '.' : a == 255 ? '#' : '+';
        }
        rows.push_back(row);
    }
    return rows;
}

} // namespace depthcull::test

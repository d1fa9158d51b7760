#include "tools/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/error.h"
#include "io/exr_writer.h"

namespace voxlux {
namespace {

constexpr double kWidth = 900, kHeight = 500;
constexpr double kLeft = 80, kRight = 300, kTop = 40, kBottom = 60;  // margins: legend on the right

std::string svgNumber(double v) {
    std::ostringstream s;
    s.precision(3);
    s << v;
    return s.str();
}

// Decades spanning [lo, hi], widened to whole powers of ten.
void decades(double lo, double hi, double& first, double& last) {
    first = std::floor(std::log10(lo));
    last = std::ceil(std::log10(hi));
    if (last <= first) last = first + 1;
}

// One plot as a group `top` pixels down the page.
std::string plotSvg(const std::string& path, const LogLogPlot& plot, double top) {
    const auto& [title, x_title, y_title, series] = plot;
    double xlo = 1e300, xhi = 0, ylo = 1e300, yhi = 0;
    for (const auto& s : series)
        for (const auto& p : s.points) {
            if (!(p.x > 0 && p.y > 0)) continue;
            xlo = std::min(xlo, p.x), xhi = std::max(xhi, p.x);
            ylo = std::min(ylo, p.y), yhi = std::max(yhi, p.y);
        }
    if (xhi <= 0 || yhi <= 0) throw InputError(path + ": nothing to plot in '" + title + "'");
    double x0, x1, y0, y1;
    decades(xlo, xhi, x0, x1);
    decades(ylo, yhi, y0, y1);
    const double pw = kWidth - kLeft - kRight, ph = kHeight - kTop - kBottom;
    auto px = [&](double x) { return kLeft + (std::log10(x) - x0) / (x1 - x0) * pw; };
    auto py = [&](double y) { return kTop + (1.0 - (std::log10(y) - y0) / (y1 - y0)) * ph; };

    std::ostringstream svg;
    svg << "<g transform='translate(0," << top << ")'>\n";
    svg << "<text x='" << kWidth / 2 - kRight / 2 << "' y='22' text-anchor='middle' font-size='15'>" << title << "</text>\n";
    // Grid lines and tick labels at every power of ten.
    for (double d = x0; d <= x1; ++d) {
        const double x = px(std::pow(10.0, d));
        svg << "<line x1='" << x << "' y1='" << kTop << "' x2='" << x << "' y2='" << kTop + ph << "' stroke='#ddd'/>\n"
            << "<text x='" << x << "' y='" << kTop + ph + 18 << "' text-anchor='middle'>" << svgNumber(std::pow(10.0, d))
            << "</text>\n";
    }
    for (double d = y0; d <= y1; ++d) {
        const double y = py(std::pow(10.0, d));
        svg << "<line x1='" << kLeft << "' y1='" << y << "' x2='" << kLeft + pw << "' y2='" << y << "' stroke='#ddd'/>\n"
            << "<text x='" << kLeft - 6 << "' y='" << y + 4 << "' text-anchor='end'>" << svgNumber(std::pow(10.0, d))
            << "</text>\n";
    }
    svg << "<rect x='" << kLeft << "' y='" << kTop << "' width='" << pw << "' height='" << ph
        << "' fill='none' stroke='black'/>\n";
    svg << "<text x='" << kLeft + pw / 2 << "' y='" << kHeight - 15 << "' text-anchor='middle'>" << x_title << "</text>\n";
    svg << "<text transform='translate(18," << kTop + ph / 2 << ") rotate(-90)' text-anchor='middle'>" << y_title
        << "</text>\n";

    double legend_y = kTop + 10;
    for (const auto& s : series) {
        std::ostringstream line;
        for (const auto& p : s.points)
            if (p.x > 0 && p.y > 0) line << px(p.x) << "," << py(p.y) << " ";
        const std::string dash = s.dashed ? " stroke-dasharray='6,3'" : s.dotted ? " stroke-dasharray='2,3'" : "";
        if (s.line)
            svg << "<polyline points='" << line.str() << "' fill='none' stroke='" << s.color << "' stroke-width='"
                << s.width << "'" << dash << "/>\n";
        for (const auto& p : s.points) {
            if (!(p.x > 0 && p.y > 0) || !s.markers) continue;
            svg << "<circle cx='" << px(p.x) << "' cy='" << py(p.y) << "' r='3.5' fill='" << s.color << "'/>\n";
            if (!p.label.empty())
                svg << "<text x='" << px(p.x) + 5 << "' y='" << py(p.y) - 5 << "' font-size='10' fill='" << s.color
                    << "'>" << p.label << "</text>\n";
        }
        svg << "<line x1='" << kWidth - kRight + 15 << "' y1='" << legend_y << "' x2='" << kWidth - kRight + 35
            << "' y2='" << legend_y << "' stroke='" << s.color << "' stroke-width='2'" << dash << "/>\n"
            << "<text x='" << kWidth - kRight + 40 << "' y='" << legend_y + 4 << "'>" << s.name << "</text>\n";
        legend_y += 18;
    }
    svg << "</g>\n";
    return svg.str();
}

}  // namespace

void writeLogLogSvg(const std::string& path, const std::vector<LogLogPlot>& plots) {
    std::ostringstream svg;
    svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kWidth << "' height='" << kHeight * plots.size()
        << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n";
    for (size_t i = 0; i < plots.size(); ++i) svg << plotSvg(path, plots[i], kHeight * double(i));
    svg << "</svg>\n";
    writeFileAtomically(path, svg.str());
}

}  // namespace voxlux

// Log-log scatter plots written as SVG: the error-against-time charts of `voxlux study` and of
// the benchmarks in docs/. Drawn here so the charts need nothing but a browser.
#pragma once
#include <string>
#include <vector>

namespace voxlux {

struct PlotPoint {
    double x = 0.0, y = 0.0;
    std::string label;
};

struct PlotSeries {
    std::string name;
    std::string color;   // any SVG colour
    std::vector<PlotPoint> points;   // joined in order
    bool dashed = false;
    bool dotted = false;
    bool markers = true;   // false: the line alone (a front, a floor)
    bool line = true;      // false: the markers alone
    double width = 1.5;    // of the line
};

struct LogLogPlot {
    std::string title, x_title, y_title;
    std::vector<PlotSeries> series;   // x and y must be > 0; other points are left out
};

// The plots stacked top to bottom in one SVG, each with axis titles and a legend, written
// atomically. Throws InputError naming `path` when a plot has nothing to show or the file
// cannot be written.
void writeLogLogSvg(const std::string& path, const std::vector<LogLogPlot>& plots);

}  // namespace voxlux

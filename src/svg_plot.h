// A small log-log scatter plot written as SVG, for the accuracy/time curves in docs/.
#pragma once
#include <string>
#include <vector>

namespace voxlux::bench {

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
};

// Writes `series` as a log-log plot (x and y must be > 0) with axis titles and a legend.
void writeLogLogSvg(const std::string& path, const std::string& title, const std::string& x_title,
                    const std::string& y_title, const std::vector<PlotSeries>& series);

}  // namespace voxlux::bench

#include "tools/study_results.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

namespace voxlux {
namespace {

const char* kColumns = "id,method,spp,seconds,rmse,delta_e_itp,pareto_rmse,pareto_delta_e";

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

// RFC 4180 fields; false when a quote is left open (a line cut short).
bool splitCsv(const std::string& line, std::vector<std::string>& fields) {
    fields.assign(1, "");
    bool in_quotes = false;
    for (size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (in_quotes) {
            if (c != '"') fields.back() += c;
            else if (i + 1 < line.size() && line[i + 1] == '"') fields.back() += '"', ++i;
            else in_quotes = false;
        } else if (c == '"') in_quotes = true;
        else if (c == ',') fields.emplace_back();
        else fields.back() += c;
    }
    return !in_quotes;
}

std::string number(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

void markFront(std::vector<StudyRow>& rows, double StudyRow::*error, bool StudyRow::*front) {
    for (auto& r : rows) {
        r.*front = std::none_of(rows.begin(), rows.end(), [&](const StudyRow& o) {
            return o.seconds <= r.seconds && o.*error <= r.*error && (o.seconds < r.seconds || o.*error < r.*error);
        });
    }
}

}  // namespace

std::string studyCsvHeader(const std::string& header) { return "# " + header + "\n" + kColumns + "\n"; }

std::string studyCsvRow(const StudyRow& r) {
    return quoted(r.id) + "," + quoted(r.method) + "," + std::to_string(r.spp) + "," + number(r.seconds) + "," +
           number(r.rmse) + "," + number(r.delta_e) + "," + (r.front_rmse ? "1" : "0") + "," +
           (r.front_delta_e ? "1" : "0") + "\n";
}

std::vector<StudyRow> readStudyCsv(const std::string& path, const std::string& header) {
    std::ifstream in(path);
    std::string line;
    if (!std::getline(in, line) || line != "# " + header) return {};
    if (!std::getline(in, line) || line != kColumns) return {};
    std::vector<StudyRow> rows;
    std::vector<std::string> f;
    while (std::getline(in, line)) {
        if (!splitCsv(line, f) || f.size() != 8) continue;
        try {
            StudyRow r{f[0], f[1], std::stoi(f[2]), std::stod(f[3]), std::stod(f[4]), std::stod(f[5]), f[6] == "1", f[7] == "1"};
            rows.push_back(r);
        } catch (const std::exception&) {
            // a number cut short: measured again
        }
    }
    return rows;
}

void markParetoFronts(std::vector<StudyRow>& rows) {
    markFront(rows, &StudyRow::rmse, &StudyRow::front_rmse);
    markFront(rows, &StudyRow::delta_e, &StudyRow::front_delta_e);
}

// The reference renders one sample at least, and no fewer seconds than a sample's slope k: a fit's
// offset t0 can be negative, which one sample's time must not inherit.
double ReferenceCurve::secondsFor(double rmse) const {
    const double spp = std::max((sigma / rmse) * (sigma / rmse), 1.0);
    return std::max(t0 + k * spp, k);
}

double ReferenceCurve::rmseAt(double seconds) const {
    const double spp = (seconds - t0) / k;
    return spp >= 1.0 ? sigma / std::sqrt(spp) : std::numeric_limits<double>::infinity();
}

std::optional<ReferenceCurve> fitReferenceCurve(const std::vector<StudyRow>& rows) {
    std::vector<const StudyRow*> ref;
    for (const auto& r : rows)
        if (r.spp > 0 && r.rmse > 0) ref.push_back(&r);
    if (ref.size() < 2) return std::nullopt;
    // seconds against spp: ordinary least squares.
    double n = double(ref.size()), sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const auto* r : ref) sx += r->spp, sy += r->seconds, sxx += double(r->spp) * r->spp, sxy += r->spp * r->seconds;
    const double det = n * sxx - sx * sx;
    if (det <= 0) return std::nullopt;
    ReferenceCurve c;
    c.k = (n * sxy - sx * sy) / det;
    c.t0 = (sy - c.k * sx) / n;
    if (!(c.k > 0)) return std::nullopt;
    // sigma: the geometric mean of rmse * sqrt(spp), i.e. least squares on log(rmse) with slope -1/2.
    const size_t from4 = size_t(std::count_if(ref.begin(), ref.end(), [](const StudyRow* r) { return r->spp >= 4; }));
    double sum = 0;
    int m = 0;
    for (const auto* r : ref)
        if (from4 < 2 || r->spp >= 4) sum += std::log(r->rmse * std::sqrt(double(r->spp))), ++m;
    c.sigma = std::exp(sum / m);
    return c;
}

std::vector<StudyRow> approximationFront(const std::vector<StudyRow>& rows) {
    std::vector<StudyRow> approx;
    for (const auto& r : rows)
        if (r.spp == 0) approx.push_back(r);
    markParetoFronts(approx);
    std::vector<StudyRow> front;
    for (const auto& r : approx)
        if (r.front_rmse) front.push_back(r);
    std::sort(front.begin(), front.end(), [](const StudyRow& a, const StudyRow& b) { return a.seconds < b.seconds; });
    return front;
}

Crossover crossoverOf(const std::vector<StudyRow>& rows, const ReferenceCurve& curve) {
    const std::vector<StudyRow> front = approximationFront(rows);
    Crossover c;
    c.min_speedup = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < front.size(); ++j) {
        // On [t_j, t_j+1) the approximation's error is e_j; the reference matches it at t_ref(e_j).
        const double t_ref = curve.secondsFor(front[j].rmse);
        const double t_next = j + 1 < front.size() ? front[j + 1].seconds : std::numeric_limits<double>::infinity();
        if (t_ref > front[j].seconds) c.seconds = std::max(c.seconds, std::min(t_next, t_ref));
        const double speedup = t_ref / front[j].seconds;
        if (speedup < c.min_speedup) c.min_speedup = speedup, c.min_speedup_id = front[j].id;
    }
    return c;
}

std::vector<BiasFloor> biasFloors(const std::vector<StudyRow>& rows) {
    std::map<std::string, BiasFloor> best;
    for (const auto& r : rows) {
        if (r.spp > 0) continue;
        auto [it, fresh] = best.emplace(r.method, BiasFloor{r.method, r.id, r.rmse, r.delta_e, r.seconds});
        if (!fresh && r.rmse < it->second.rmse) it->second = {r.method, r.id, r.rmse, r.delta_e, r.seconds};
    }
    std::vector<BiasFloor> out;
    for (auto& [m, f] : best) out.push_back(f);
    std::sort(out.begin(), out.end(), [](const BiasFloor& a, const BiasFloor& b) { return a.rmse < b.rmse; });
    return out;
}

}  // namespace voxlux

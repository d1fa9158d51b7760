// The measurements of `voxlux study` and what follows from them: the CSV it writes and resumes
// from, the Pareto fronts, each method's bias floor, and the Monte Carlo reference's error-time
// curve with the crossover against the approximations (docs/accuracy.md).
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace voxlux {

struct StudyRow {
    std::string id;                      // StudyConfig::id()
    std::string method;                  // StudyConfig::method
    int spp = 0;
    double seconds = 0;                  // every stage but reading the file, best of the repeats
    double rmse = 0;                     // against the ground truth, its own noise taken out
    double delta_e = 0;                  // mean Delta E_ITP against the ground truth
    bool front_rmse = false, front_delta_e = false;   // on the Pareto front of that error against time
};

// The CSV: a first line `# <header>` that says what the rows were measured against, then a
// column line, then one row per render. Rows are appended as they finish, so a study that is
// stopped keeps what it measured.
std::string studyCsvHeader(const std::string& header);
std::string studyCsvRow(const StudyRow& row);
// The rows of `path` if its first line is `# <header>`; nothing when the file is absent or was
// measured against something else. A last line cut short by a crash is dropped.
std::vector<StudyRow> readStudyCsv(const std::string& path, const std::string& header);

// Marks the rows on the Pareto front of each error against seconds: no other row is at least as
// fast and at least as accurate and better in one of the two.
void markParetoFronts(std::vector<StudyRow>& rows);

// The reference's cost and noise: seconds = t0 + k * spp, RMSE = sigma / sqrt(spp), fitted by
// least squares to the reference rows (sigma from rows of 4 spp or more when there are two).
struct ReferenceCurve {
    double t0 = 0, k = 0, sigma = 0;
    double secondsFor(double rmse) const;   // to reach `rmse` (one sample's at least)
    double rmseAt(double seconds) const;    // reached in `seconds` (infinity below one sample)
};
std::optional<ReferenceCurve> fitReferenceCurve(const std::vector<StudyRow>& rows);

// The approximations' (every method but the reference's) own RMSE Pareto front, fastest first:
// at a time budget t the best of them is the most accurate row not slower than t.
std::vector<StudyRow> approximationFront(const std::vector<StudyRow>& rows);

// Where the approximations (every method but the reference) stand against the reference curve.
struct Crossover {
    double seconds = 0;                  // below this an approximation beats the reference at equal time
    double min_speedup = 0;              // the least, over the approximations' RMSE front, of
    std::string min_speedup_id;          // the reference's time for that RMSE / the approximation's time
};
Crossover crossoverOf(const std::vector<StudyRow>& rows, const ReferenceCurve& curve);

// Each approximating method's lowest RMSE over its settings: the error more time does not remove.
struct BiasFloor {
    std::string method, id;
    double rmse = 0, delta_e = 0, seconds = 0;
};
std::vector<BiasFloor> biasFloors(const std::vector<StudyRow>& rows);

}  // namespace voxlux

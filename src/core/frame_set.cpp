#include "core/frame_set.h"

#include <algorithm>
#include <charconv>
#include <stdexcept>

namespace voxlux {
namespace {

const char* const kSyntax = "expected FIRST-LAST[xSTEP] or a list of them, e.g. 1-240x2,300";

int64_t rangeCount(const FrameRange& r) { return (int64_t(r.last) - r.first) / r.step + 1; }

// A frame number (a leading '-' allowed) or step: digits only, within int.
int parseNumber(std::string_view text) {
    int value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size()) throw std::invalid_argument(kSyntax);
    return value;
}

}  // namespace

FrameSet::FrameSet(int first, int last) {
    if (first > last) throw std::invalid_argument("the first frame is after the last");
    ranges_.push_back({first, last, 1});
}

void FrameSet::append(FrameRange r) {
    if (!ranges_.empty() && r.first <= ranges_.back().last)
        throw std::invalid_argument("frames must increase: " + std::to_string(r.first) + " follows " + std::to_string(ranges_.back().last));
    ranges_.push_back(r);
}

FrameSet FrameSet::parse(const std::string& spec) {
    FrameSet set;
    size_t begin = 0;
    do {
        const size_t comma = std::min(spec.find(',', begin), spec.size());
        const std::string_view item = std::string_view(spec).substr(begin, comma - begin);
        const size_t dash = item.find('-', 1), times = item.find('x');   // "-5--1": a frame may be negative
        FrameRange r;
        r.first = parseNumber(item.substr(0, std::min(dash, times)));
        r.last = dash == std::string_view::npos ? r.first : parseNumber(item.substr(dash + 1, times - std::min(times, dash + 1)));
        if (times != std::string_view::npos) {
            if (dash == std::string_view::npos || times < dash) throw std::invalid_argument(kSyntax);
            r.step = parseNumber(item.substr(times + 1));
            if (r.step < 1) throw std::invalid_argument("the step must be at least 1");
        }
        if (r.first > r.last)
            throw std::invalid_argument("frames " + std::string(item) + ": the first frame is after the last");
        r.last -= int((int64_t(r.last) - r.first) % r.step);   // the last frame the step reaches
        if (r.first == r.last) r.step = 1;
        set.append(r);
        begin = comma + 1;
    } while (begin <= spec.size());
    return set;
}

void FrameSet::add(int frame) {
    if (!ranges_.empty() && ranges_.back().step == 1 && int64_t(frame) == int64_t(ranges_.back().last) + 1) ranges_.back().last = frame;
    else append({frame, frame, 1});
}

FrameSet FrameSet::among(const FrameSet& present) const {
    FrameSet out;
    for (int64_t k = 0; k < present.count(); ++k) {
        const int f = present.at(k);
        const bool in = std::any_of(ranges_.begin(), ranges_.end(),
                                    [f](const FrameRange& r) { return f >= r.first && f <= r.last && (int64_t(f) - r.first) % r.step == 0; });
        if (in) out.add(f);
    }
    return out;
}

FrameSet FrameSet::notAmong(const FrameSet& present) const {
    FrameSet out;
    const auto emit = [&out](int64_t first, int64_t last, int step) {
        if (first <= last) out.append({int(first), int(last), first == last ? 1 : step});
    };
    int64_t k = 0;
    for (const FrameRange& r : ranges_) {
        int64_t next = r.first;   // the first frame of r not yet emitted or skipped
        for (; k < present.count() && present.at(k) <= r.last; ++k) {
            const int64_t f = present.at(k);
            if (f < next || (f - r.first) % r.step != 0) continue;
            emit(next, f - r.step, r.step);
            next = f + r.step;
        }
        emit(next, r.last, r.step);
    }
    return out;
}

int64_t FrameSet::count() const {
    int64_t n = 0;
    for (const auto& r : ranges_) n += rangeCount(r);
    return n;
}

int FrameSet::at(int64_t index) const {
    for (const auto& r : ranges_) {
        if (index < rangeCount(r)) return int(r.first + index * r.step);
        index -= rangeCount(r);
    }
    throw std::out_of_range("frame index past the last frame");
}

FrameSet FrameSet::slice(int64_t begin, int64_t count) const {
    FrameSet out;
    for (const auto& r : ranges_) {
        const int64_t n = rangeCount(r);
        if (begin >= n) {
            begin -= n;
            continue;
        }
        const int64_t take = std::min(count, n - begin);
        if (take <= 0) break;
        const int first = int(r.first + begin * r.step);
        out.ranges_.push_back({first, int(first + (take - 1) * r.step), take == 1 ? 1 : r.step});
        count -= take;
        begin = 0;
    }
    return out;
}

std::string FrameSet::text() const {
    std::string out;
    for (const auto& r : ranges_) {
        if (!out.empty()) out += ',';
        out += std::to_string(r.first);
        if (r.last == r.first) continue;
        out += '-';
        out += std::to_string(r.last);
        if (r.step == 1) continue;
        out += 'x';
        out += std::to_string(r.step);
    }
    return out;
}

}  // namespace voxlux

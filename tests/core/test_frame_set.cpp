// Frame specs as a farm writes them, parsed and walked without expanding a range.
#include <gtest/gtest.h>

#include <stdexcept>

#include "core/frame_set.h"

namespace voxlux::test {
namespace {

std::vector<int> allFrames(const FrameSet& s) {
    std::vector<int> out;
    for (int64_t k = 0; k < s.count(); ++k) out.push_back(s.at(k));
    return out;
}

TEST(FrameSet, RangesStepsAndListsWalkInOrder) {
    EXPECT_EQ(allFrames(FrameSet::parse("7")), (std::vector<int>{7}));
    EXPECT_EQ(allFrames(FrameSet::parse("1-4")), (std::vector<int>{1, 2, 3, 4}));
    // The step's last frame is the last it reaches: 1-10x4 ends at 9.
    const FrameSet stepped = FrameSet::parse("1-10x4");
    EXPECT_EQ(allFrames(stepped), (std::vector<int>{1, 5, 9}));
    EXPECT_EQ(stepped.last(), 9);
    EXPECT_EQ(allFrames(FrameSet::parse("1,5,10-14x2,20")), (std::vector<int>{1, 5, 10, 12, 14, 20}));
    EXPECT_EQ(allFrames(FrameSet::parse("-3--1")), (std::vector<int>{-3, -2, -1}));
    EXPECT_TRUE(FrameSet::parse("1-240").isRange());
    EXPECT_FALSE(FrameSet::parse("1-240x2").isRange());
}

TEST(FrameSet, AHugeRangeIsNeverExpanded) {
    const FrameSet s = FrameSet::parse("0-2000000000,2100000000-2147483647x7");
    EXPECT_EQ(s.count(), 2000000001 + (2147483647 - 2100000000) / 7 + 1);
    EXPECT_EQ(s.at(2000000000), 2000000000);
    EXPECT_EQ(s.at(2000000001), 2100000000);
    EXPECT_EQ(s.at(s.count() - 1), 2100000000 + (2147483647 - 2100000000) / 7 * 7);
    EXPECT_THROW(s.at(s.count()), std::out_of_range);
}

// Which frames of a range are on disk, and which are not, cut from the small set of files without
// walking the range.
TEST(FrameSet, AmongAndNotAmongSplitARangeByTheFramesPresent) {
    const FrameSet disk = FrameSet::parse("1-2,4,7-8,11");
    EXPECT_EQ(FrameSet::parse("1-10").among(disk).text(), "1-2,4,7-8");
    EXPECT_EQ(FrameSet::parse("1-10").notAmong(disk).text(), "3,5-6,9-10");
    // A step keeps its lattice: of 1-11x2 (1, 3, 5, 7, 9, 11), 1, 7 and 11 are there.
    EXPECT_EQ(FrameSet::parse("1-11x2").among(disk).text(), "1,7,11");
    EXPECT_EQ(FrameSet::parse("1-11x2").notAmong(disk).text(), "3-5x2,9");
    EXPECT_EQ(FrameSet::parse("3,5-6").among(disk).count(), 0);
    EXPECT_EQ(FrameSet::parse("3,5-6").notAmong(disk).text(), "3,5-6");
    EXPECT_EQ(FrameSet::parse("1-2").notAmong(disk).count(), 0);
    const FrameSet huge = FrameSet::parse("1-2000000000");
    EXPECT_EQ(huge.among(FrameSet::parse("1")).text(), "1");
    EXPECT_EQ(huge.notAmong(FrameSet::parse("1")).text(), "2-2000000000");
    EXPECT_EQ(huge.notAmong(FrameSet()).text(), "1-2000000000");
}

TEST(FrameSet, TextReadsBackAsTheSameSet) {
    for (const char* spec : {"7", "1-240", "1-239x2", "1,5,10-14x2,20", "-3--1"}) {
        EXPECT_EQ(FrameSet::parse(spec).text(), spec);
        EXPECT_EQ(FrameSet::parse(FrameSet::parse(spec).text()), FrameSet::parse(spec)) << spec;
    }
    EXPECT_EQ(FrameSet::parse("1-240x2").text(), "1-239x2");
    EXPECT_EQ(FrameSet::parse("5-5x3").text(), "5");
}

// A farm's chunks: consecutive slices cover the set once, in order.
TEST(FrameSet, SlicesCutTheSetIntoChunks) {
    const FrameSet s = FrameSet::parse("1-9x2,20-22");
    EXPECT_EQ(s.slice(0, 2).text(), "1-3x2");
    EXPECT_EQ(s.slice(2, 2).text(), "5-7x2");
    EXPECT_EQ(s.slice(4, 2).text(), "9,20");
    EXPECT_EQ(s.slice(6, 2).text(), "21-22");
    EXPECT_EQ(s.slice(6, 100).text(), "21-22");
    EXPECT_EQ(s.slice(8, 2).count(), 0);
}

TEST(FrameSet, AddMergesNeighbours) {
    FrameSet s;
    for (int f : {3, 4, 5, 9, 11, 12}) s.add(f);
    EXPECT_EQ(s.text(), "3-5,9,11-12");
    EXPECT_THROW(s.add(12), std::invalid_argument);
}

TEST(FrameSet, MalformedSpecsAreRefusedWithTheProblem) {
    const auto problem = [](const std::string& spec) {
        try {
            FrameSet::parse(spec);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    const std::string syntax = "expected FIRST-LAST[xSTEP] or a list of them, e.g. 1-240x2,300";
    for (const char* bad : {"", "a", "1-", "-", "1-5x", "1x2", "1-5x2x3", "1,,2", "1-3000000000", "1.5", " 1"})
        EXPECT_EQ(problem(bad), syntax) << bad;
    EXPECT_EQ(problem("5-1"), "frames 5-1: the first frame is after the last");
    EXPECT_EQ(problem("1-5x0"), "the step must be at least 1");
    EXPECT_EQ(problem("1-5x-2"), "the step must be at least 1");
    EXPECT_EQ(problem("3,1"), "frames must increase: 1 follows 3");
    EXPECT_EQ(problem("1-5,5"), "frames must increase: 5 follows 5");
}

}  // namespace
}  // namespace voxlux::test

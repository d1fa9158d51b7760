// Nuke's .chan text: frame tx ty tz rx ry rz per line (eight columns from a camera, the field of
// view skipped), blank lines skipped, and every other line refused with its number.
#include "core/error.h"
#include "scene/chan_file.h"
#include "test_support.h"

namespace voxlux::test {
namespace {

TEST(ChanFile, ReadsAnAxisAndACameraExport) {
    const ChanTrack track = parseChan("1 0 1.5 -2 0 90 0\n\n2.5\t1e1 0 0  10 20 30 \n3 0 0 0 0 0 0 54.43\n", "smoke.chan");
    const std::vector<TransformKey>& keys = track.keys;
    EXPECT_TRUE(track.vertical_fov.empty());   // not every line has the camera's column
    ASSERT_EQ(keys.size(), 3u);
    EXPECT_EQ(keys[0].frame, 1.0);
    EXPECT_EQ(keys[0].translate, glm::vec3(0.0f, 1.5f, -2.0f));
    EXPECT_EQ(keys[0].rotate, glm::vec3(0.0f, 90.0f, 0.0f));
    EXPECT_EQ(keys[1].frame, 2.5);
    EXPECT_EQ(keys[1].translate, glm::vec3(10.0f, 0.0f, 0.0f));
    EXPECT_EQ(keys[1].rotate, glm::vec3(10.0f, 20.0f, 30.0f));
    EXPECT_EQ(keys[2].frame, 3.0);
    EXPECT_EQ(keys[2].scale, glm::vec3(1.0f));
}

TEST(ChanFile, RefusesWhatIsNotAKeyWithTheLine) {
    EXPECT_EQ(inputErrorOf([] { parseChan("1 0 0 0 0 0 0\n2 0 0 0 0\n", "a.chan"); }),
              "a.chan: line 2: expected frame tx ty tz rx ry rz (7 numbers, or 8 from a camera), found 5 fields");
    EXPECT_EQ(inputErrorOf([] { parseChan("1 0 0 0 0 0 x\n", "a.chan"); }), "a.chan: line 1: \"x\" is not a finite number");
    EXPECT_EQ(inputErrorOf([] { parseChan("1 0 0 0 0 0 nan\n", "a.chan"); }), "a.chan: line 1: \"nan\" is not a finite number");
    EXPECT_EQ(inputErrorOf([] { parseChan("1 0 0 0 0 0 1,5\n", "a.chan"); }), "a.chan: line 1: \"1,5\" is not a finite number");
    EXPECT_EQ(inputErrorOf([] { parseChan("1 2e9 0 0 0 0 0\n", "a.chan"); }), "a.chan: line 1: value 2e9 lies beyond +-1e9");
    EXPECT_EQ(inputErrorOf([] { parseChan("2 0 0 0 0 0 0\n2 0 0 0 0 0 0\n", "a.chan"); }),
              "a.chan: line 2: frame 2 does not follow frame 2.0 (frames must increase)");
    EXPECT_EQ(inputErrorOf([] { parseChan("\n  \n", "a.chan"); }), "a.chan: no keys (expected lines of frame tx ty tz rx ry rz)");
    EXPECT_EQ(inputErrorOf([] { readChanFile("/nonexistent/a.chan"); }), "/nonexistent/a.chan: cannot open .chan file");
}

}  // namespace
}  // namespace voxlux::test

// SPDX-License-Identifier: LGPL-2.1-or-later
// The numbers of an OBJ file: what the check before the loader passes, the
// loader must read as the same value; what it would read otherwise is
// refused with the file and the line.
#include "caustic/mesh.hpp"
#include "scratch_dir.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

using namespace caustic;

namespace {

// A scratch folder of its own per test (dir_).
class ObjNumbers : public caustic::testing::ScratchDirTest {
 protected:
  std::filesystem::path write(const std::string& text) {
    const auto path = dir_ / "face.obj";
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  // The message of load_obj's refusal, "" when it loads.
  std::string refusal(const std::string& text) {
    try {
      load_obj(write(text));
      return "";
    } catch (const SceneError& e) {
      EXPECT_EQ(e.key(), "mesh");
      return e.what();
    }
  }

};

constexpr const char* kFace = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

TEST_F(ObjNumbers, HexIsRefusedWithItsLine) {
  // strtod reads 0x1p3 as 8, the loader as 0: the vertex moved without a
  // word (the square's corner (8, 1) loaded as (0, 1)), or a triangle lost
  // its area and was refused as that.
  EXPECT_NE(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0x1p3 1 0\nf 1 2 3\nf 2 4 3\n").find("line 4: \"0x1p3\""),
            std::string::npos);
  for (const char* hex : {"0x1p3", "0X8", "-0x1.8p1", "0x10"}) {
    const std::string why = refusal("v 0 0 0\nv 1 0 0\nv 0 " + std::string(hex) + " 0\nf 1 2 3\n");
    EXPECT_NE(why.find("face.obj line 3: \"" + std::string(hex) + "\" is not a decimal number"), std::string::npos)
        << hex << ": " << why;
  }
  // In a normal, a texture coordinate and a colour as in a position.
  EXPECT_NE(refusal(std::string(kFace) + "vn 0 0 0x1\n").find("line 5: \"0x1\" is not a decimal"), std::string::npos);
  EXPECT_NE(refusal(std::string(kFace) + "vt 0x0 0\n").find("line 5: \"0x0\" is not a decimal"), std::string::npos);
  EXPECT_NE(refusal("v 0 0 0 1 1 1\nv 1 0 0 1 1 1\nv 0 1 0 1 1 0x1p-1\nf 1 2 3\n").find("line 3"), std::string::npos);
}

TEST_F(ObjNumbers, AnExponentPastADoublesIsRefusedWithItsLine) {
  // The loader scales by 5^exponent: a zero written 0e500 became NaN, a
  // small number with a large exponent Inf; strtod read both as finite.
  for (const char* big : {"0e500", "0.0000000001e450", "1e+309"}) {
    const std::string why = refusal("v 0 0 0\nv 1 0 0\nv 0 1 " + std::string(big) + "\nf 1 2 3\n");
    EXPECT_NE(why.find("line 3:"), std::string::npos) << big << ": " << why;
    EXPECT_NE(why.find(big), std::string::npos) << why;
  }
  // A small number stays: its exponent is negative.
  EXPECT_EQ(refusal("v 0 0 1e-400\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "");
}

TEST_F(ObjNumbers, EveryDecimalFormTheLoaderReadsLoadsAsWritten) {
  const Mesh mesh = load_obj(write("v +.5 5. -1.5E-3\nv 1e2 0 0\nv 0 1 0.25e+1\nf 1 2 3\n"));
  ASSERT_EQ(mesh.positions.size(), 3u);
  EXPECT_FLOAT_EQ(mesh.positions[0].x, 0.5f);
  EXPECT_FLOAT_EQ(mesh.positions[0].y, 5.0f);
  EXPECT_FLOAT_EQ(mesh.positions[0].z, -0.0015f);
  EXPECT_FLOAT_EQ(mesh.positions[1].x, 100.0f);
  EXPECT_FLOAT_EQ(mesh.positions[2].z, 2.5f);
  // Not numbers: a point alone, an exponent with no digits, a sign alone.
  for (const char* word : {".", "1e", "-", "1e+", ".e1"})
    EXPECT_NE(refusal("v 0 0 0\nv 1 0 0\nv 0 1 " + std::string(word) + "\nf 1 2 3\n").find("line 3"),
              std::string::npos)
        << word;
}

TEST_F(ObjNumbers, AFaceNamingAVertexOrNormalNotThereIsSaidWithItsLine) {
  // The file and the face's corner, not only "a face refers to a vertex that
  // does not exist" with neither.
  EXPECT_NE(refusal(std::string(kFace) + "f 1 2 9\nv 1 1 0\n").find("face.obj line 5: a face's corner names vertex 9, "
                                                                    "which does not exist (the file holds 4)"),
            std::string::npos);
  // Counted back from the vertices read so far, not from the file's last.
  EXPECT_NE(refusal("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n").find("line 3: a face's corner names vertex -3, which "
                                                                      "does not exist (counted back from the last: 2 "
                                                                      "so far)"),
            std::string::npos);
  EXPECT_NE(refusal(std::string(kFace) + "vn 0 0 1\nf 1//1 2//2 3//1\n").find("line 6: a face's corner names normal 2"),
            std::string::npos);
  const std::string back = refusal(std::string(kFace) + "vn 0 0 1\nf 1//-2 2//1 3//1\n");
  EXPECT_NE(back.find("line 6: a face's corner names normal -2"), std::string::npos) << back;
  // A face before the vertices it names, and relative corners within what was read, load.
  EXPECT_EQ(refusal("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"), "");
  EXPECT_EQ(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf -3//-1 -2//-1 -1//-1\n"), "");
}

TEST_F(ObjNumbers, AByteOrderMarkIsNoStatement) {
  // Some editors write one first; it was refused as line 1's unknown statement.
  const Mesh mesh = load_obj(write("\xef\xbb\xbf" + std::string(kFace)));
  EXPECT_EQ(mesh.triangles.size(), 1u);
  // Anywhere else it is a statement no OBJ has.
  const std::string why = refusal(std::string(kFace) + "\xef\xbb\xbfv 0 0 1\n");
  EXPECT_NE(why.find("line 5: this line's statement is not supported"), std::string::npos) << why;
}

}  // namespace

// Paths of the bundled cloth_ball sample (samples/README.md) and of the tools.
#pragma once

#include <string>
#include <vector>

namespace snag::test {

inline const std::string kSampleDir = std::string(SNAG_SOURCE_DIR) + "/samples/cloth_ball";
inline const std::string kClothPc2 = kSampleDir + "/cloth.pc2";
inline const std::string kClothRest = kSampleDir + "/cloth_rest.obj";
inline const std::string kBodyPc2 = kSampleDir + "/body.pc2";
inline const std::string kBodyRest = kSampleDir + "/body_rest.obj";
inline const std::string kObjSequenceDir = kSampleDir + "/obj_sequence";
inline const std::string kObjPattern = kObjSequenceDir + "/cloth_ball_%04d.obj";
inline const std::string kObjGlob = kObjSequenceDir + "/cloth_ball_*.obj";

/// The sample as two point caches with their topology meshes (cloth, then body).
inline std::vector<std::string> sample_pc2_inputs() {
  return {kClothPc2, "-t", kClothRest, kBodyPc2, "-t", kBodyRest};
}

}  // namespace snag::test

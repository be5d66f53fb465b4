#include <cstring>
#include <memory>
#include <mutex>

#include "common/common.h"

namespace climbsim::common {

mjModel* CompileMjcfString(const std::string& xml, std::string* error) {
  // MuJoCo's XML loader keeps process-wide state: one load at a time in the program. The
  // top file has a bare name: 2.2.2 prefixes every include with the top file's folder.
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* name = "climbsim_adhesion_model.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
    *error = "cannot create the model in MuJoCo's VFS";
    return nullptr;
  }
  std::memcpy(vfs->filedata[vfs->nfile - 1], xml.data(), xml.size());
  char err[1024] = {0};
  mjModel* m = mj_loadXML(name, vfs.get(), err, sizeof(err));
  mj_deleteVFS(vfs.get());
  if (m == nullptr) *error = err;
  return m;
}

}  // namespace climbsim::common

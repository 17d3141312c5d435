#include "common/thread_name.h"

#include <pthread.h>

namespace esdslam {

void NameThisThread(const std::string& name) {
#if defined(__linux__)
  constexpr std::size_t kLinuxLimit = 15;  // characters, without the terminating zero
  pthread_setname_np(pthread_self(), name.substr(0, kLinuxLimit).c_str());
#else
  (void)name;
#endif
}

}  // namespace esdslam

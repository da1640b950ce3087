// The native MRPT rawlog decoder (both layouts, gzip or plain) on arbitrary
// bytes: read_rawlog() and read_log()'s content sniffing.
#include <cstdlib>

#include "fuzz_support.h"
#include "hmt/common/error.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/rawlog.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Classes the native decoder does not know go to MRPT's reader plugin,
  // whose deserializers are not hardened (rawlog.h): not under test here.
  // A plugin that cannot be loaded is an InputError naming the class.
  setenv("HMT_IO_MRPT_PLUGIN", "/nonexistent/libhmt_io_mrpt.so", 1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static hmt::fuzz::ScratchFile file("rawlog");
  const std::string& path = file.write(data, size);
  try {
    hmt::fuzz::check_log(hmt::io::read_rawlog(path));
  } catch (const hmt::Error&) {
  }
  try {
    // A CARMEN-looking input goes to the CARMEN reader, the rest to the
    // rawlog decoder with its "neither format" diagnosis.
    if (hmt::io::detect_log_format(path) != hmt::io::LogFormat::kRosBag)
      hmt::fuzz::check_log(hmt::io::read_log(path));
  } catch (const hmt::Error&) {
  }
  return 0;
}

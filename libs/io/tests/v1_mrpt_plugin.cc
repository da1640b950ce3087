// Stands for an MRPT plugin built before the reader streamed: it exports
// only the whole-file reader's entry point, which hmt_io must not look for
// (mrpt_stream_test.cc). Its signature is of no matter: it is never called.
extern "C" __attribute__((visibility("default"))) int hmt_io_mrpt_read_rawlog_v1() { return 2; }

// The GPU-visible structs of kernels/layout.h must have the same size, field offsets
// and bytes in OpenCL C as in C++. tests/kernels/layout_check.cl holds the field table;
// it is included here as C++ (its kernels compile only as OpenCL C), and embedded as
// OpenCL C source by tests/CMakeLists.txt.
#include "host/backend.h"
#include "host/opencl/cl_runtime.h"
#include "test_kernels/layout_check_cl.h"
#include "tests/kernels/layout_check.cl"

#include <gtest/gtest.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>
#include "tests/test_env.h"

namespace {

using namespace masq;
using namespace masq::kernel;

bool allow_no_opencl() { return masq::test::missing_backends_allowed(); }

struct Entry {
  std::string what;
  int value;
};

// The C++ view of the table: sizeof then every field's offset, per struct.
std::vector<Entry> cpp_layout() {
  std::vector<Entry> v;
#define CPP_OFFSET_F(T, f) v.push_back({#T "." #f, static_cast<int>(offsetof(T, f))});
#define CPP_OFFSET_A(T, f, n) CPP_OFFSET_F(T, f)
#define CPP_SIZES(T)                                           \
  v.push_back({"sizeof(" #T ")", static_cast<int>(sizeof(T))}); \
  MASQ_LAYOUT_##T(CPP_OFFSET_F, CPP_OFFSET_A)
  MASQ_LAYOUT_STRUCTS(CPP_SIZES)
#undef CPP_SIZES
  return v;
}

// Word index (offset / 4) of every field element, in table order.
#define CPP_WORDS_F(T, f) w.push_back(static_cast<int>(offsetof(T, f) / 4));
#define CPP_WORDS_A(T, f, n) \
  for (int j = 0; j < (n); ++j) w.push_back(static_cast<int>(offsetof(T, f) / 4) + j);

class OpenClLayout : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    try {
      rt_ = std::make_unique<opencl::Runtime>(opencl::open_runtime());
    } catch (const BackendUnavailable& e) {
      unavailable_ = e.what();
      return;
    }
    try {
      program_ = opencl::build_program(*rt_, opencl_src::layout_check_cl, opencl::base_build_options(*rt_),
                                       "tests/kernels/layout_check.cl")
                     .program;
    } catch (const std::exception& e) {
      build_error_ = e.what();
    }
  }
  static void TearDownTestSuite() {
    program_ = cl::Program();
    rt_.reset();
  }
  void SetUp() override {
    if (!build_error_.empty()) FAIL() << build_error_;
    if (rt_) return;
    if (allow_no_opencl()) GTEST_SKIP() << unavailable_;
    FAIL() << unavailable_ << " (the setup script installs PoCL; MASQ_ALLOW_MISSING_BACKENDS=1 skips)";
  }

  template <class T>
  void check_roundtrip(const char* type, const std::vector<int>& field_words) {
    SCOPED_TRACE(type);
    constexpr int kWords = static_cast<int>(sizeof(T) / 4);
    // Every byte belongs to a listed field: the table misses no field.
    ASSERT_EQ(static_cast<int>(field_words.size()), kWords) << "layout_check.cl lists a wrong number of words";
    const int count = 37;
    std::vector<std::uint32_t> in(static_cast<std::size_t>(count) * kWords);
    for (std::size_t w = 0; w < in.size(); ++w) // distinct normal floats: bits survive float loads
      in[w] = std::bit_cast<std::uint32_t>(static_cast<float>(w + 1));
    cl_int err = CL_SUCCESS;
    const std::size_t bytes = in.size() * 4;
    cl::Buffer in_buf(rt_->context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, in.data(), &err);
    ASSERT_EQ(err, CL_SUCCESS);
    cl::Buffer out_buf(rt_->context, CL_MEM_WRITE_ONLY, bytes, nullptr, &err);
    ASSERT_EQ(err, CL_SUCCESS);
    cl::Buffer flat_buf(rt_->context, CL_MEM_WRITE_ONLY, bytes, nullptr, &err);
    ASSERT_EQ(err, CL_SUCCESS);
    cl::Kernel k(program_, (std::string("roundtrip_") + type).c_str(), &err);
    ASSERT_EQ(err, CL_SUCCESS) << opencl::cl_error_name(err);
    cl_uint arg = 0; // in the order of roundtrip_<type>'s parameters
    ASSERT_EQ(k.setArg(arg++, in_buf), CL_SUCCESS);
    ASSERT_EQ(k.setArg(arg++, out_buf), CL_SUCCESS);
    ASSERT_EQ(k.setArg(arg++, flat_buf), CL_SUCCESS);
    ASSERT_EQ(k.setArg(arg++, cl_int(count)), CL_SUCCESS);
    ASSERT_EQ(rt_->queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(count)), CL_SUCCESS);
    std::vector<std::uint32_t> out(in.size()), flat(in.size());
    ASSERT_EQ(rt_->queue.enqueueReadBuffer(out_buf, CL_TRUE, 0, bytes, out.data()), CL_SUCCESS);
    ASSERT_EQ(rt_->queue.enqueueReadBuffer(flat_buf, CL_TRUE, 0, bytes, flat.data()), CL_SUCCESS);
    EXPECT_EQ(std::memcmp(in.data(), out.data(), bytes), 0) << "struct copy changed bytes";
    for (int i = 0; i < count; ++i)
      for (int f = 0; f < kWords; ++f) {
        const std::size_t at = static_cast<std::size_t>(i) * kWords;
        ASSERT_EQ(flat[at + f], in[at + field_words[f]]) << "element " << i << ", field word " << f;
      }
  }

  static std::unique_ptr<opencl::Runtime> rt_;
  static cl::Program program_;
  static std::string unavailable_;
  static std::string build_error_;
};

std::unique_ptr<opencl::Runtime> OpenClLayout::rt_;
cl::Program OpenClLayout::program_;
std::string OpenClLayout::unavailable_;
std::string OpenClLayout::build_error_;

TEST_F(OpenClLayout, SizesAndOffsetsMatchCpp) {
  const std::vector<Entry> expected = cpp_layout();
  std::vector<cl_int> got(expected.size() + 8, -1);
  cl_int err = CL_SUCCESS;
  cl::Buffer buf(rt_->context, CL_MEM_WRITE_ONLY, got.size() * sizeof(cl_int), nullptr, &err);
  ASSERT_EQ(err, CL_SUCCESS);
  cl::Kernel k(program_, "layout_sizes", &err);
  ASSERT_EQ(err, CL_SUCCESS) << opencl::cl_error_name(err);
  const cl_uint out_arg = 0; // layout_sizes' one parameter
  ASSERT_EQ(k.setArg(out_arg, buf), CL_SUCCESS);
  ASSERT_EQ(rt_->queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1)), CL_SUCCESS);
  ASSERT_EQ(rt_->queue.enqueueReadBuffer(buf, CL_TRUE, 0, got.size() * sizeof(cl_int), got.data()), CL_SUCCESS);
  ASSERT_EQ(got[expected.size()], static_cast<cl_int>(expected.size())) << "entry count";
  for (std::size_t i = 0; i < expected.size(); ++i)
    EXPECT_EQ(got[i], expected[i].value) << expected[i].what;
}

TEST_F(OpenClLayout, RoundTripThroughEveryStruct) {
#define CPP_ROUNDTRIP(T)                        \
  {                                             \
    std::vector<int> w;                         \
    MASQ_LAYOUT_##T(CPP_WORDS_F, CPP_WORDS_A)   \
    check_roundtrip<T>(#T, w);                  \
    if (HasFatalFailure()) return;              \
  }
  MASQ_LAYOUT_STRUCTS(CPP_ROUNDTRIP)
#undef CPP_ROUNDTRIP
}

} // namespace

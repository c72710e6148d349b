#include "hardware/triple_buffer.h"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <thread>

namespace lap::hardware {
namespace {

// A value whose fields must agree: any torn read (half of one publish, half of another) shows.
struct Payload {
  int64_t sequence = 0;
  std::array<int64_t, 32> copies{};
};

TEST(TripleBuffer, ReaderSeesWholeValuesInOrderUnderContention) {
  TripleBuffer<Payload> buf;
  constexpr int64_t kCount = 2000000;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (int64_t i = 1; i <= kCount; ++i) {
      Payload& p = buf.write_slot();
      p.sequence = i;
      p.copies.fill(i);
      buf.publish();
    }
    done.store(true);
  });
  int64_t last = 0;
  int64_t torn = 0;
  int64_t backwards = 0;
  int64_t fresh = 0;
  while (true) {
    const bool finished = done.load();
    if (buf.update()) {
      ++fresh;
      const Payload& p = buf.read();
      for (const int64_t c : p.copies) torn += c != p.sequence ? 1 : 0;
      backwards += p.sequence < last ? 1 : 0;
      last = p.sequence;
    }
    if (finished && !buf.update()) break;
  }
  writer.join();
  if (buf.update()) last = buf.read().sequence;
  EXPECT_EQ(torn, 0);
  EXPECT_EQ(backwards, 0);
  EXPECT_EQ(buf.read().sequence, kCount);  // the newest value always arrives
  EXPECT_GT(fresh, 1);
}

TEST(TripleBuffer, UpdateSaysWhetherSomethingNewArrived) {
  TripleBuffer<int> buf(7);
  EXPECT_FALSE(buf.update());
  EXPECT_EQ(buf.read(), 7);
  buf.publish(8);
  buf.publish(9);
  EXPECT_TRUE(buf.update());
  EXPECT_EQ(buf.read(), 9);
  EXPECT_FALSE(buf.update());
  EXPECT_EQ(buf.latest(), 9);
}

}  // namespace
}  // namespace lap::hardware

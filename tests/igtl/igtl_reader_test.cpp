// The stream reader against messages packed by the reference library: framing across any
// split, the CRC, unknown types, and a hostile header that asks for more than the limit.
#include "osteon/devices/igtl_reader.h"

#include <gtest/gtest.h>

#include "igtlQuaternionTrackingDataMessage.h"
#include "igtlStringMessage.h"
#include "igtlTrackingDataMessage.h"
#include "igtlTransformMessage.h"

namespace osteon::devices {
namespace {

std::vector<std::uint8_t> packed(::igtl::MessageBase& m) {
  m.Pack();
  const auto* p = static_cast<const std::uint8_t*>(m.GetPackPointer());
  return {p, p + m.GetPackSize()};
}

std::vector<std::uint8_t> transformBytes(float x, float y, float z) {
  ::igtl::TransformMessage::Pointer t = ::igtl::TransformMessage::New();
  t->SetDeviceName("Stylus");
  ::igtl::Matrix4x4 m;
  ::igtl::IdentityMatrix(m);
  m[0][3] = x;
  m[1][3] = y;
  m[2][3] = z;
  t->SetMatrix(m);
  return packed(*t);
}

std::vector<std::uint8_t> stringBytes(const char* text) {
  ::igtl::StringMessage::Pointer s = ::igtl::StringMessage::New();
  s->SetDeviceName("Note");
  s->SetString(text);
  return packed(*s);
}

TEST(IgtlReader, FramesMessagesSplitAnywhereAndSkipsOtherTypes) {
  std::vector<std::uint8_t> stream = transformBytes(1.0f, 2.0f, 3.0f);
  const std::vector<std::uint8_t> note = stringBytes("hello");
  stream.insert(stream.end(), note.begin(), note.end());
  const std::vector<std::uint8_t> second = transformBytes(4.0f, 5.0f, 6.0f);
  stream.insert(stream.end(), second.begin(), second.end());
  for (std::size_t chunk : {std::size_t(1), std::size_t(7), std::size_t(58), stream.size()}) {
    IgtlStreamReader reader({"TRANSFORM"});
    std::vector<glm::dvec3> got;
    for (std::size_t at = 0; at < stream.size(); at += chunk) {
      ASSERT_TRUE(reader.feed(stream.data() + at, std::min(chunk, stream.size() - at)));
      IgtlMessage m;
      while (reader.next(m)) {
        EXPECT_EQ(m.name, "Stylus");
        glm::dmat4 t;
        ASSERT_TRUE(decodeIgtlTransform(m, t));
        got.push_back(glm::dvec3(t[3]));
      }
    }
    ASSERT_EQ(got.size(), 2u) << chunk;
    EXPECT_EQ(got[1], glm::dvec3(4.0, 5.0, 6.0));
    EXPECT_EQ(reader.stats().skipped, 1u);
  }
}

TEST(IgtlReader, ABadCrcIsSkippedAndCounted) {
  std::vector<std::uint8_t> bad = transformBytes(1.0f, 2.0f, 3.0f);
  bad[kIgtlHeaderBytes + 40] ^= 0x10;  // a bit of the translation
  const std::vector<std::uint8_t> good = transformBytes(7.0f, 8.0f, 9.0f);
  bad.insert(bad.end(), good.begin(), good.end());
  IgtlStreamReader reader({"TRANSFORM"});
  reader.feed(bad.data(), bad.size());
  IgtlMessage m;
  ASSERT_TRUE(reader.next(m));
  glm::dmat4 t;
  ASSERT_TRUE(decodeIgtlTransform(m, t));
  EXPECT_EQ(glm::dvec3(t[3]), glm::dvec3(7.0, 8.0, 9.0));
  EXPECT_EQ(reader.stats().crcErrors, 1u);
  EXPECT_FALSE(reader.next(m));
}

TEST(IgtlReader, ABodyOverTheLimitBreaksTheStreamBeforeAnyAllocation) {
  std::vector<std::uint8_t> huge = transformBytes(1.0f, 2.0f, 3.0f);
  for (std::size_t i = 42; i < 50; ++i) huge[i] = 0xFF;  // body size 2^64 - 1
  IgtlStreamReader reader({}, 1024);
  reader.feed(huge.data(), kIgtlHeaderBytes);
  IgtlMessage m;
  EXPECT_FALSE(reader.next(m));
  EXPECT_TRUE(reader.broken());
  EXPECT_FALSE(reader.feed(huge.data(), huge.size()));
  EXPECT_NE(reader.brokenReason().find("over the limit"), std::string::npos);
}

TEST(IgtlReader, ATransformOfTheWrongSizeOrNotFiniteIsRefused) {
  IgtlMessage m;
  m.body.assign(47, 0);
  glm::dmat4 t;
  EXPECT_FALSE(decodeIgtlTransform(m, t));
  m.body.assign(48, 0xFF);  // NaNs
  EXPECT_FALSE(decodeIgtlTransform(m, t));
}

// TDATA and QTDATA from the reference library: the element named, or the first.
TEST(IgtlReader, TrackingDataGivesTheNamedElementsPose) {
  ::igtl::TrackingDataMessage::Pointer td = ::igtl::TrackingDataMessage::New();
  for (const char* tool : {"Probe", "Stylus"}) {
    ::igtl::TrackingDataElement::Pointer e = ::igtl::TrackingDataElement::New();
    e->SetName(tool);
    ::igtl::Matrix4x4 m;
    ::igtl::IdentityMatrix(m);
    m[0][3] = tool[0] == 'P' ? 1.0f : 5.0f;
    m[1][0] = 1.0f;  // a shear only to see the columns land where they belong
    e->SetMatrix(m);
    td->AddTrackingDataElement(e);
  }
  const std::vector<std::uint8_t> tdBytes = packed(*td);
  ::igtl::QuaternionTrackingDataMessage::Pointer qt = ::igtl::QuaternionTrackingDataMessage::New();
  ::igtl::QuaternionTrackingDataElement::Pointer q = ::igtl::QuaternionTrackingDataElement::New();
  q->SetName("Stylus");
  q->SetPosition(7.0f, 8.0f, 9.0f);
  q->SetQuaternion(0.0f, 0.0f, 0.70710678f, 0.70710678f);  // 90 degrees about z
  qt->AddQuaternionTrackingDataElement(q);
  const std::vector<std::uint8_t> qtBytes = packed(*qt);

  IgtlStreamReader reader({"TDATA", "QTDATA"});
  reader.feed(tdBytes.data(), tdBytes.size());
  reader.feed(qtBytes.data(), qtBytes.size());
  IgtlMessage m;
  glm::dmat4 t;
  ASSERT_TRUE(reader.next(m));
  ASSERT_TRUE(decodeIgtlPose(m, "Stylus", t));
  EXPECT_EQ(t[3].x, 5.0);
  EXPECT_EQ(t[0].y, 1.0);  // row 1, column 0
  ASSERT_TRUE(decodeIgtlPose(m, "", t));
  EXPECT_EQ(t[3].x, 1.0);
  EXPECT_FALSE(decodeIgtlPose(m, "Needle", t));
  ASSERT_TRUE(reader.next(m));
  ASSERT_TRUE(decodeIgtlPose(m, "Stylus", t));
  EXPECT_EQ(glm::dvec3(t[3]), glm::dvec3(7.0, 8.0, 9.0));
  EXPECT_NEAR(t[0].y, 1.0, 1e-6);  // x goes to y
}

// A type not asked for streams past whatever its size (here over the limit), fed in pieces.
TEST(IgtlReader, AHugeMessageOfAnotherTypeIsSkippedWithoutBeingKept) {
  std::vector<std::uint8_t> stream = stringBytes(std::string(5000, 'x').c_str());
  const std::vector<std::uint8_t> after = transformBytes(1.0f, 2.0f, 3.0f);
  stream.insert(stream.end(), after.begin(), after.end());
  IgtlStreamReader reader({"TRANSFORM"}, 1024);
  IgtlMessage m;
  int got = 0;
  for (std::size_t at = 0; at < stream.size(); at += 100) {
    ASSERT_TRUE(reader.feed(stream.data() + at, std::min<std::size_t>(100, stream.size() - at)));
    while (reader.next(m)) ++got;
  }
  EXPECT_EQ(got, 1);
  EXPECT_EQ(reader.stats().skipped, 1u);
  EXPECT_FALSE(reader.broken());
}

}  // namespace
}  // namespace osteon::devices

// Content flag values, names and their round trips.
#include <gtest/gtest.h>

#include "cmkit/contents.h"

using namespace cmkit;

TEST(Contents, BitValuesAreTheOriginals) {
  EXPECT_EQ(contents::kSolid, 1u);
  EXPECT_EQ(contents::kOpaque, 2u);
  EXPECT_EQ(contents::kWater, 4u);
  EXPECT_EQ(contents::kPlayerClip, 8u);
  EXPECT_EQ(contents::kMonsterClip, 16u);
  EXPECT_EQ(contents::kMoveableClip, 32u);
  EXPECT_EQ(contents::kIkClip, 64u);
  EXPECT_EQ(contents::kBlood, 128u);
  EXPECT_EQ(contents::kBody, 256u);
  EXPECT_EQ(contents::kProjectile, 512u);
  EXPECT_EQ(contents::kCorpse, 1024u);
  EXPECT_EQ(contents::kRenderModel, 2048u);
  EXPECT_EQ(contents::kTrigger, 4096u);
  EXPECT_EQ(contents::kAasSolid, 8192u);
  EXPECT_EQ(contents::kAasObstacle, 16384u);
  EXPECT_EQ(contents::kFlashlightTrigger, 32768u);
  EXPECT_EQ(contents::kAreaPortal, 1u << 20);
  EXPECT_EQ(contents::kNoCsg, 1u << 21);
  EXPECT_EQ(contents::kMaskPlayerSolid, 1u | 8u | 256u);
  EXPECT_EQ(contents::kMaskMonsterSolid, 1u | 16u | 256u);
  EXPECT_EQ(contents::kMaskDeadSolid, 1u | 8u);
  EXPECT_EQ(contents::kMaskShotBoundingBox, 1u | 256u);
  EXPECT_EQ(contents::kMaskShotRenderModel, 1u | 2048u);
}

TEST(Contents, NamesAreInBitOrder) {
  auto names = contentNames();
  ASSERT_EQ(names.size(), 16u);
  for (size_t i = 0; i < names.size(); ++i) EXPECT_EQ(names[i].flag, 1u << i) << names[i].name;
  EXPECT_EQ(names[11].name, "renderModel");
  EXPECT_EQ(names[13].name, "aas_solid");
}

TEST(Contents, FromString) {
  EXPECT_EQ(*contentsFromString("solid"), 1u);
  EXPECT_EQ(*contentsFromString("solid,opaque"), 3u);
  EXPECT_EQ(*contentsFromString(" water , playerclip "), 12u);
  EXPECT_EQ(*contentsFromString(""), 0u);
  EXPECT_EQ(*contentsFromString("solid,solid"), 1u);
}

TEST(Contents, UnknownNameIsAnErrorQuotingIt) {
  auto r = contentsFromString("solid,lava");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("'lava'"), std::string::npos) << r.error().message;
  EXPECT_FALSE(contentsFromString("Solid").ok());   // names are case-sensitive
  EXPECT_FALSE(contentsFromString("solid,").ok());  // an empty name is not a name
}

TEST(Contents, ToString) {
  EXPECT_EQ(contentsToString(0), "");
  EXPECT_EQ(contentsToString(3), "solid,opaque");
  EXPECT_EQ(contentsToString(contents::kTrigger | contents::kWater), "water,trigger");
  EXPECT_EQ(contentsToString(contents::kAreaPortal | contents::kSolid), "solid");
  EXPECT_EQ(contentsToStringExact(contents::kAreaPortal | contents::kSolid), "solid,0x100000");
  EXPECT_EQ(contentsToStringExact(0x80000000u), "0x80000000");
}

TEST(Contents, RoundTripEveryFlagCombination) {
  for (std::uint32_t flags = 0; flags < (1u << 16); flags += 37) {
    auto back = contentsFromString(contentsToString(flags));
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(*back, flags);
  }
  for (const ContentName& n : contentNames()) EXPECT_EQ(*contentsFromString(n.name), n.flag);
}

TEST(Contents, MaskParsing) {
  EXPECT_EQ(*parseContentsMask("solid,water"), 5u);
  EXPECT_EQ(*parseContentsMask("9"), 9u);
  EXPECT_EQ(*parseContentsMask("0x10"), 16u);
  EXPECT_EQ(*parseContentsMask("4294967295"), 0xFFFFFFFFu);
  EXPECT_FALSE(parseContentsMask("4294967296").ok());
  EXPECT_EQ(*parseContentsMask("-1"), 0xFFFFFFFFu);
  EXPECT_EQ(*parseContentsMask("-2147483648"), 0x80000000u);
  EXPECT_FALSE(parseContentsMask("-2147483649").ok());
  EXPECT_FALSE(parseContentsMask("12abc").ok());
  EXPECT_FALSE(parseContentsMask("0xZZ").ok());
}

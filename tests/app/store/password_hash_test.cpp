// Instructors' password hashing (app/store/password_hash.h) against published test vectors:
// PBKDF2-HMAC-SHA-1 from RFC 6070 §2 and PBKDF2-HMAC-SHA-256 from RFC 7914 §11, HMAC-SHA-256
// from RFC 4231 §4.2; then the stored form (salted, slow, compared in constant time).

#include "app/store/password_hash.h"

#include <gtest/gtest.h>

#include <QByteArray>
#include <set>

namespace lap::app {
namespace {

QByteArray hex(const char* h) { return QByteArray::fromHex(h); }

TEST(Hmac, Rfc4231TestCase1) {
  // RFC 4231 §4.2: key = 20 bytes of 0x0b, data = "Hi There".
  EXPECT_EQ(hmac(QCryptographicHash::Sha256, QByteArray(20, '\x0b'), "Hi There").toHex(),
            "b0344c61d8db38535ca8afceaf0bf12b881dc200c9833da726e9376c2e32cff7");
}

TEST(Hmac, Rfc4231TestCase6KeyLongerThanABlock) {
  // RFC 4231 §4.7: a 131-byte key of 0xaa is hashed first (RFC 2104 §2).
  EXPECT_EQ(hmac(QCryptographicHash::Sha256, QByteArray(131, '\xaa'),
                 "Test Using Larger Than Block-Size Key - Hash Key First")
                .toHex(),
            "60e431591ee0b67f0d8a26aacbf5b77f8e0bc6213728c5140546040f0ee37f54");
}

struct Pbkdf2Vector {
  QCryptographicHash::Algorithm algorithm;
  QByteArray password;
  QByteArray salt;
  int iterations;
  int length;
  const char* derived_hex;
};

TEST(Pbkdf2, Rfc6070HmacSha1Vectors) {
  const Pbkdf2Vector vectors[] = {
      {QCryptographicHash::Sha1, "password", "salt", 1, 20,
       "0c60c80f961f0e71f3a9b524af6012062fe037a6"},
      {QCryptographicHash::Sha1, "password", "salt", 2, 20,
       "ea6c014dc72d6f8ccd1ed92ace1d41f0d8de8957"},
      {QCryptographicHash::Sha1, "password", "salt", 4096, 20,
       "4b007901b765489abead49d926f721d065a429c1"},
      // Two blocks of output, the second cut short.
      {QCryptographicHash::Sha1, "passwordPASSWORDpassword", "saltSALTsaltSALTsaltSALTsaltSALTsalt",
       4096, 25, "3d2eec4fe41c849b80c8d83662c0e44a8b291a964cf2f07038"},
      // Bytes after a NUL count.
      {QCryptographicHash::Sha1, QByteArray("pass\0word", 9), QByteArray("sa\0lt", 5), 4096, 16,
       "56fa6aa75548099dcc37d7f03425e0c3"},
  };
  for (const Pbkdf2Vector& v : vectors) {
    EXPECT_EQ(pbkdf2(v.algorithm, v.password, v.salt, v.iterations, v.length).toHex(),
              QByteArray(v.derived_hex))
        << v.password.constData() << " c=" << v.iterations;
  }
}

TEST(Pbkdf2, Rfc7914HmacSha256Vectors) {
  // RFC 7914 §11, the two PBKDF2-HMAC-SHA256 vectors (64 bytes: two blocks).
  EXPECT_EQ(pbkdf2(QCryptographicHash::Sha256, "passwd", "salt", 1, 64),
            hex("55ac046e56e3089fec1691c22544b605f94185216dde0465e68b9d57c20dacbc"
                "49ca9cccf179b645991664b39d77ef317c71b845b1e30bd509112041d3a19783"));
  EXPECT_EQ(pbkdf2(QCryptographicHash::Sha256, "Password", "NaCl", 80000, 64),
            hex("4ddcd8f60b98be21830cee5ef22701f9641a4418d04c0414aeff08876b34ab56"
                "a1d425a1225833549adb841b51c9b3176a272bdebba1d078478f62b397f33c8d"));
}

TEST(Pbkdf2, RefusesNonsense) {
  EXPECT_TRUE(pbkdf2(QCryptographicHash::Sha256, "p", "s", 0, 32).isEmpty());
  EXPECT_TRUE(pbkdf2(QCryptographicHash::Sha256, "p", "s", 1, 0).isEmpty());
}

TEST(ConstantTimeEqual, ComparesEveryByte) {
  EXPECT_TRUE(constant_time_equal("abcd", "abcd"));
  EXPECT_FALSE(constant_time_equal("abcd", "abce"));  // last byte
  EXPECT_FALSE(constant_time_equal("xbcd", "abcd"));  // first byte
  EXPECT_FALSE(constant_time_equal("abc", "abcd"));
  EXPECT_TRUE(constant_time_equal("", ""));
}

TEST(PasswordHash, SaltedPerUserAndVerified) {
  Result<PasswordHash> a = hash_password("correct horse", 1000);
  Result<PasswordHash> b = hash_password("correct horse", 1000);
  ASSERT_TRUE(a.ok()) << a.message();
  ASSERT_TRUE(b.ok()) << b.message();
  EXPECT_EQ(a->salt.size(), kPasswordSaltBytes);
  EXPECT_EQ(a->hash.size(), kPasswordHashBytes);
  EXPECT_EQ(a->iterations, 1000);
  // A fresh salt each time: the same password does not give the same hash.
  EXPECT_NE(a->salt, b->salt);
  EXPECT_NE(a->hash, b->hash);
  // The hash is PBKDF2-HMAC-SHA256 of the password's UTF-8 under that salt.
  EXPECT_EQ(a->hash, pbkdf2(QCryptographicHash::Sha256, "correct horse", a->salt, 1000, 32));
  EXPECT_TRUE(verify_password("correct horse", a.value()));
  EXPECT_FALSE(verify_password("correct horsf", a.value()));
  EXPECT_FALSE(verify_password("", a.value()));
  PasswordHash fewer = a.value();
  fewer.iterations = 999;  // the count is part of what is checked
  EXPECT_FALSE(verify_password("correct horse", fewer));
}

TEST(PasswordHash, NonAsciiPasswordsAreTheirUtf8) {
  Result<PasswordHash> h = hash_password(QStringLiteral("Zürich-Ärztin-ß"), 10);
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(h->hash, pbkdf2(QCryptographicHash::Sha256, QStringLiteral("Zürich-Ärztin-ß").toUtf8(),
                            h->salt, 10, 32));
  EXPECT_TRUE(verify_password(QStringLiteral("Zürich-Ärztin-ß"), h.value()));
  EXPECT_FALSE(verify_password(QStringLiteral("Zurich-Arztin-ss"), h.value()));
}

TEST(PasswordHash, DefaultIsOwaspsWorkFactor) {
  EXPECT_EQ(kPasswordIterations, 600000);
  Result<PasswordHash> h = hash_password("a long enough password");
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(h->iterations, 600000);
  EXPECT_TRUE(verify_password("a long enough password", h.value()));
}

TEST(PasswordHash, RefusesShortPasswords) {
  Result<PasswordHash> h = hash_password("1234567", 10);
  ASSERT_FALSE(h.ok());
  EXPECT_NE(h.message().find("at least 8 characters"), std::string::npos) << h.message();
}

TEST(PasswordHash, SaltsDoNotRepeat) {
  std::set<QByteArray> salts;
  for (int i = 0; i < 200; ++i) salts.insert(random_salt());
  EXPECT_EQ(salts.size(), 200U);
}

}  // namespace
}  // namespace lap::app

#include "app/store/password_hash.h"

#include <QRandomGenerator>
#include <algorithm>
#include <cstdint>

namespace lap::app {
namespace {

// SHA-1's and SHA-256's block size (RFC 2104 §2: B = 64 for both).
constexpr int kHmacBlockBytes = 64;

// HMAC's two padded keys (RFC 2104 §2), computed once per password so that each PBKDF2 round
// hashes only the pads and the previous round's output.
struct HmacKey {
  QByteArray inner_pad;
  QByteArray outer_pad;
};

HmacKey hmac_key(QCryptographicHash::Algorithm algorithm, const QByteArray& key) {
  QByteArray k = key.size() > kHmacBlockBytes ? QCryptographicHash::hash(key, algorithm) : key;
  k.resize(kHmacBlockBytes, '\0');
  HmacKey pads{k, k};
  for (int i = 0; i < kHmacBlockBytes; ++i) {
    pads.inner_pad[i] = static_cast<char>(k[i] ^ 0x36);
    pads.outer_pad[i] = static_cast<char>(k[i] ^ 0x5c);
  }
  return pads;
}

QByteArray hmac_with(const HmacKey& key, QCryptographicHash& inner, QCryptographicHash& outer,
                     const QByteArray& message) {
  inner.reset();
  inner.addData(key.inner_pad);
  inner.addData(message);
  outer.reset();
  outer.addData(key.outer_pad);
  outer.addData(inner.result());
  return outer.result();
}

}  // namespace

QByteArray hmac(QCryptographicHash::Algorithm algorithm, const QByteArray& key,
                const QByteArray& message) {
  QCryptographicHash inner(algorithm);
  QCryptographicHash outer(algorithm);
  return hmac_with(hmac_key(algorithm, key), inner, outer, message);
}

QByteArray pbkdf2(QCryptographicHash::Algorithm algorithm, const QByteArray& password,
                  const QByteArray& salt, int iterations, int length) {
  if (iterations < 1 || length < 1) return {};
  const HmacKey key = hmac_key(algorithm, password);
  QCryptographicHash inner(algorithm);
  QCryptographicHash outer(algorithm);
  QByteArray derived;
  derived.reserve(length);
  // RFC 8018 §5.2: T_i = U_1 ^ U_2 ^ ... ^ U_c, U_1 = PRF(P, S || INT(i)), U_j = PRF(P, U_{j-1}).
  for (uint32_t block = 1; derived.size() < length; ++block) {
    QByteArray first = salt;
    first.append(static_cast<char>((block >> 24) & 0xff));
    first.append(static_cast<char>((block >> 16) & 0xff));
    first.append(static_cast<char>((block >> 8) & 0xff));
    first.append(static_cast<char>(block & 0xff));
    QByteArray u = hmac_with(key, inner, outer, first);
    QByteArray t = u;
    for (int j = 1; j < iterations; ++j) {
      u = hmac_with(key, inner, outer, u);
      for (int b = 0; b < t.size(); ++b) t[b] = static_cast<char>(t[b] ^ u[b]);
    }
    derived.append(t.left(std::min<qsizetype>(t.size(), length - derived.size())));
  }
  return derived;
}

bool constant_time_equal(const QByteArray& a, const QByteArray& b) {
  if (a.size() != b.size()) return false;  // the lengths are public (a hash's is fixed)
  unsigned char difference = 0;
  for (qsizetype i = 0; i < a.size(); ++i) {
    difference |= static_cast<unsigned char>(a[i] ^ b[i]);
  }
  return difference == 0;
}

QByteArray random_salt() {
  QByteArray salt(kPasswordSaltBytes, '\0');
  QRandomGenerator* generator = QRandomGenerator::system();
  for (int i = 0; i < kPasswordSaltBytes; ++i) {
    salt[i] = static_cast<char>(generator->bounded(256));
  }
  return salt;
}

Result<PasswordHash> hash_password(const QString& password, int iterations) {
  if (password.size() < kPasswordMinLength) {
    return diagnostic("password: expected at least " + std::to_string(kPasswordMinLength) +
                      " characters, got " + std::to_string(password.size()));
  }
  if (iterations < 1) {
    return diagnostic("password: iterations: expected at least 1, got " +
                      std::to_string(iterations));
  }
  PasswordHash h;
  h.salt = random_salt();
  h.iterations = iterations;
  h.hash =
      pbkdf2(QCryptographicHash::Sha256, password.toUtf8(), h.salt, iterations, kPasswordHashBytes);
  return h;
}

bool verify_password(const QString& password, const PasswordHash& stored) {
  if (stored.iterations < 1 || stored.hash.isEmpty()) return false;
  const QByteArray candidate = pbkdf2(QCryptographicHash::Sha256, password.toUtf8(), stored.salt,
                                      stored.iterations, static_cast<int>(stored.hash.size()));
  return constant_time_equal(candidate, stored.hash);
}

}  // namespace lap::app

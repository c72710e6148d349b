#pragma once
/// \file
/// Instructors' passwords, stored as a salted slow hash: PBKDF2 (RFC 8018 §5.2, formerly RFC
/// 2898) with HMAC-SHA-256 (RFC 2104) as its pseudorandom function, a per-user random salt of 16
/// bytes from the operating system's generator, and 600,000 iterations — the OWASP Password
/// Storage Cheat Sheet's figure for PBKDF2-HMAC-SHA256 (May 2023). The iteration count is stored
/// with each hash, so that raising it later leaves old hashes checkable. Checked against the test
/// vectors of RFC 6070 (HMAC-SHA-1) and RFC 7914 §11 (HMAC-SHA-256); compared in constant time.
///
/// Written over Qt Core's QCryptographicHash so that the store needs Qt Core and Qt SQL only
/// (QPasswordDigestor would pull in Qt Network).

#include <QByteArray>
#include <QCryptographicHash>
#include <QString>

#include "core/result.h"

namespace lap::app {

/// OWASP's PBKDF2-HMAC-SHA256 work factor (Password Storage Cheat Sheet, 2023).
inline constexpr int kPasswordIterations = 600'000;
inline constexpr int kPasswordSaltBytes = 16;
inline constexpr int kPasswordHashBytes = 32;  ///< one SHA-256 block of output
/// Passwords shorter than this are refused when set (NIST SP 800-63B §5.1.1.2: at least 8).
inline constexpr int kPasswordMinLength = 8;

/// HMAC (RFC 2104) of `message` under `key` with the hash `algorithm` (SHA-1 or SHA-256).
[[nodiscard]] QByteArray hmac(QCryptographicHash::Algorithm algorithm, const QByteArray& key,
                              const QByteArray& message);

/// PBKDF2 (RFC 8018 §5.2) with HMAC over `algorithm`: `length` bytes derived from `password`
/// and `salt` in `iterations` rounds. Both `iterations` and `length` must be positive.
[[nodiscard]] QByteArray pbkdf2(QCryptographicHash::Algorithm algorithm, const QByteArray& password,
                                const QByteArray& salt, int iterations, int length);

/// Whether two byte strings are equal, in a time that depends on their lengths only (never on
/// where they first differ), so that a comparison does not tell an attacker how much matched.
[[nodiscard]] bool constant_time_equal(const QByteArray& a, const QByteArray& b);

/// A stored password: its salt, its PBKDF2-HMAC-SHA256 hash and the iterations used.
struct PasswordHash {
  QByteArray salt;
  QByteArray hash;
  int iterations = kPasswordIterations;
};

/// A fresh salt from the operating system's cryptographic generator (QRandomGenerator::system).
[[nodiscard]] QByteArray random_salt();

/// Hashes `password` with a fresh salt. Refuses a password shorter than kPasswordMinLength
/// characters or an iteration count below 1.
[[nodiscard]] Result<PasswordHash> hash_password(const QString& password,
                                                 int iterations = kPasswordIterations);

/// Whether `password` is the one `stored` was made from (UTF-8 bytes, constant-time compare).
[[nodiscard]] bool verify_password(const QString& password, const PasswordHash& stored);

}  // namespace lap::app

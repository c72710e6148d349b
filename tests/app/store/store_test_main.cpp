// The store's tests need a QCoreApplication: Qt SQL loads its drivers (QSQLITE, QPSQL) as
// plugins, which only an application object can do.

#include <gtest/gtest.h>

#include <QCoreApplication>

int main(int argc, char** argv) {
  QCoreApplication app(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

#pragma once
// Switching the C locale to one with a decimal comma, for the tests that libbpm's number
// text (files, TetGen's input and output) does not depend on the locale.

#include <catch2/catch.hpp>

#include <clocale>
#include <locale>
#include <string>

namespace bpm::test_support {

// scripts/setup.sh generates it (Debian compiles only C and POSIX).
constexpr const char* kCommaLocale = "de_DE.UTF-8";

// Sets the whole C locale (setlocale(LC_ALL, ...)) and the C++ global locale
// (std::locale::global, which every stream made afterwards imbues: a decimal comma and
// "." as the thousands separator of integers) to kCommaLocale for its lifetime, as a host
// program that calls std::locale::global(std::locale("")) does, and restores both at the end, also when a check throws, so that the tests after
// it run under the locale they expect. Fails the test - a skip would hide exactly the
// machines where nobody looked - when the locale is missing or has no decimal comma.
class CommaLocale {
public:
    CommaLocale() : previous_(std::setlocale(LC_ALL, nullptr)) {
        const bool set = std::setlocale(LC_ALL, kCommaLocale) != nullptr;
        if (set) previous_global_ = std::locale::global(std::locale(kCommaLocale));
        const bool comma = set && std::string(std::localeconv()->decimal_point) == ",";
        if (!comma) restore();  // no destructor after a throw here
        if (!set)
            FAIL("the locale " << kCommaLocale << " is not available: run scripts/setup.sh "
                               "(it generates it with `localedef -i de_DE -f UTF-8 de_DE.UTF-8`)");
        if (!comma) FAIL("the locale " << kCommaLocale << " has no decimal comma");
    }
    ~CommaLocale() { restore(); }
    CommaLocale(const CommaLocale&) = delete;
    CommaLocale& operator=(const CommaLocale&) = delete;

private:
    // std::locale::global also sets the C locale when the locale has a name: the C one last.
    void restore() {
        std::locale::global(previous_global_);
        std::setlocale(LC_ALL, previous_.c_str());
    }
    std::string previous_;
    std::locale previous_global_;
};

}  // namespace bpm::test_support

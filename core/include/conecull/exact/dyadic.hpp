// Exact dyadic rationals m * 2^e (m an arbitrary-precision integer): every double is one, and
// ring operations (+, -, *) stay inside, so no division is ever needed. Used by the exact CCD
// fallback, where products of many coordinates would leave the double range of expansions.
#pragma once

#include <cstdint>
#include <vector>

namespace conecull::exact {

class BigInt {
   public:
    BigInt() = default;
    explicit BigInt(uint64_t v, bool negative = false);
    bool is_zero() const { return mag_.empty(); }
    int sign() const { return is_zero() ? 0 : (neg_ ? -1 : 1); }
    BigInt operator-() const;
    friend BigInt operator+(const BigInt& a, const BigInt& b);
    friend BigInt operator-(const BigInt& a, const BigInt& b) { return a + (-b); }
    friend BigInt operator*(const BigInt& a, const BigInt& b);
    BigInt shifted_left(uint64_t bits) const;
    uint64_t trailing_zero_bits() const;   // of a non-zero value
    BigInt shifted_right_exact(uint64_t bits) const;  // drops bits known to be zero

   private:
    static int cmp_mag(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b);
    static std::vector<uint32_t> add_mag(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b);
    static std::vector<uint32_t> sub_mag(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b);  // |a| >= |b|
    void trim();
    std::vector<uint32_t> mag_;  // little-endian limbs
    bool neg_ = false;
};

class Dyadic {
   public:
    Dyadic() = default;
    explicit Dyadic(double x);  // exact
    static Dyadic pow2(int64_t e);
    int sign() const { return m_.sign(); }
    bool is_zero() const { return m_.is_zero(); }
    Dyadic operator-() const;
    friend Dyadic operator+(const Dyadic& a, const Dyadic& b);
    friend Dyadic operator-(const Dyadic& a, const Dyadic& b) { return a + (-b); }
    friend Dyadic operator*(const Dyadic& a, const Dyadic& b);
    Dyadic half() const;  // exact

   private:
    Dyadic(BigInt m, int64_t e) : m_(std::move(m)), e_(e) { normalize(); }
    void normalize();
    BigInt m_;
    int64_t e_ = 0;
};

inline int compare(const Dyadic& a, const Dyadic& b) { return (a - b).sign(); }

}  // namespace conecull::exact

#include "conecull/exact/dyadic.hpp"

#include <algorithm>
#include <cmath>

namespace conecull::exact {

BigInt::BigInt(uint64_t v, bool negative) {
    while (v) {
        mag_.push_back(static_cast<uint32_t>(v));
        v >>= 32;
    }
    neg_ = negative && !mag_.empty();
}

void BigInt::trim() {
    while (!mag_.empty() && mag_.back() == 0) mag_.pop_back();
    if (mag_.empty()) neg_ = false;
}

BigInt BigInt::operator-() const {
    BigInt r = *this;
    if (!r.is_zero()) r.neg_ = !r.neg_;
    return r;
}

int BigInt::cmp_mag(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    if (a.size() != b.size()) return a.size() < b.size() ? -1 : 1;
    for (size_t i = a.size(); i-- > 0;)
        if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
    return 0;
}

std::vector<uint32_t> BigInt::add_mag(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    std::vector<uint32_t> r(std::max(a.size(), b.size()) + 1, 0);
    uint64_t carry = 0;
    for (size_t i = 0; i < r.size(); ++i) {
        uint64_t s = carry;
        if (i < a.size()) s += a[i];
        if (i < b.size()) s += b[i];
        r[i] = static_cast<uint32_t>(s);
        carry = s >> 32;
    }
    return r;
}

std::vector<uint32_t> BigInt::sub_mag(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    std::vector<uint32_t> r(a.size(), 0);
    int64_t borrow = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        int64_t s = static_cast<int64_t>(a[i]) - borrow - (i < b.size() ? static_cast<int64_t>(b[i]) : 0);
        borrow = s < 0;
        if (s < 0) s += (int64_t(1) << 32);
        r[i] = static_cast<uint32_t>(s);
    }
    return r;
}

BigInt operator+(const BigInt& a, const BigInt& b) {
    BigInt r;
    if (a.neg_ == b.neg_) {
        r.mag_ = BigInt::add_mag(a.mag_, b.mag_);
        r.neg_ = a.neg_;
    } else {
        const int c = BigInt::cmp_mag(a.mag_, b.mag_);
        if (c == 0) return BigInt();
        if (c > 0) {
            r.mag_ = BigInt::sub_mag(a.mag_, b.mag_);
            r.neg_ = a.neg_;
        } else {
            r.mag_ = BigInt::sub_mag(b.mag_, a.mag_);
            r.neg_ = b.neg_;
        }
    }
    r.trim();
    return r;
}

BigInt operator*(const BigInt& a, const BigInt& b) {
    if (a.is_zero() || b.is_zero()) return BigInt();
    BigInt r;
    r.mag_.assign(a.mag_.size() + b.mag_.size(), 0);
    for (size_t i = 0; i < a.mag_.size(); ++i) {
        uint64_t carry = 0;
        for (size_t j = 0; j < b.mag_.size(); ++j) {
            const uint64_t cur = r.mag_[i + j] + static_cast<uint64_t>(a.mag_[i]) * b.mag_[j] + carry;
            r.mag_[i + j] = static_cast<uint32_t>(cur);
            carry = cur >> 32;
        }
        size_t k = i + b.mag_.size();
        while (carry) {
            const uint64_t cur = r.mag_[k] + carry;
            r.mag_[k++] = static_cast<uint32_t>(cur);
            carry = cur >> 32;
        }
    }
    r.neg_ = a.neg_ != b.neg_;
    r.trim();
    return r;
}

BigInt BigInt::shifted_left(uint64_t bits) const {
    if (is_zero() || bits == 0) return *this;
    BigInt r;
    const size_t limbs = bits / 32, rem = bits % 32;
    r.mag_.assign(limbs, 0);
    uint32_t carry = 0;
    for (uint32_t x : mag_) {
        r.mag_.push_back(rem ? (x << rem) | carry : x);
        carry = rem ? x >> (32 - rem) : 0;
    }
    if (carry) r.mag_.push_back(carry);
    r.neg_ = neg_;
    r.trim();
    return r;
}

uint64_t BigInt::trailing_zero_bits() const {
    uint64_t n = 0;
    for (uint32_t x : mag_) {
        if (x == 0) {
            n += 32;
            continue;
        }
        return n + static_cast<uint64_t>(__builtin_ctz(x));
    }
    return n;
}

BigInt BigInt::shifted_right_exact(uint64_t bits) const {
    if (is_zero() || bits == 0) return *this;
    BigInt r;
    const size_t limbs = bits / 32, rem = bits % 32;
    for (size_t i = limbs; i < mag_.size(); ++i) {
        uint32_t v = rem ? mag_[i] >> rem : mag_[i];
        if (rem && i + 1 < mag_.size()) v |= mag_[i + 1] << (32 - rem);
        r.mag_.push_back(v);
    }
    r.neg_ = neg_;
    r.trim();
    return r;
}

Dyadic::Dyadic(double x) {
    if (x == 0.0) return;
    int exp = 0;
    const double frac = std::frexp(std::fabs(x), &exp);  // |x| = frac * 2^exp, frac in [0.5, 1)
    const uint64_t mant = static_cast<uint64_t>(std::ldexp(frac, 53));
    m_ = BigInt(mant, x < 0);
    e_ = exp - 53;
    normalize();
}

Dyadic Dyadic::pow2(int64_t e) { return Dyadic(BigInt(1), e); }

void Dyadic::normalize() {
    if (m_.is_zero()) {
        e_ = 0;
        return;
    }
    const uint64_t tz = m_.trailing_zero_bits();
    if (tz) {
        m_ = m_.shifted_right_exact(tz);
        e_ += static_cast<int64_t>(tz);
    }
}

Dyadic Dyadic::operator-() const { return Dyadic(-m_, e_); }

Dyadic operator+(const Dyadic& a, const Dyadic& b) {
    if (a.is_zero()) return b;
    if (b.is_zero()) return a;
    if (a.e_ <= b.e_) return Dyadic(a.m_ + b.m_.shifted_left(static_cast<uint64_t>(b.e_ - a.e_)), a.e_);
    return Dyadic(a.m_.shifted_left(static_cast<uint64_t>(a.e_ - b.e_)) + b.m_, b.e_);
}

Dyadic operator*(const Dyadic& a, const Dyadic& b) { return Dyadic(a.m_ * b.m_, a.e_ + b.e_); }

Dyadic Dyadic::half() const { return is_zero() ? *this : Dyadic(m_, e_ - 1); }

}  // namespace conecull::exact

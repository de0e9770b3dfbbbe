#include "image_sequence.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

namespace depthtouch::media::detail {

std::vector<long long> imageSequenceNumbers(const std::string &pattern)
{
    std::vector<long long> numbers;
    const std::size_t pct = pattern.find('%');
    if (pct == std::string::npos || pattern.find('%', pct + 1) != std::string::npos)
        return numbers;
    std::size_t d = pct + 1;
    while (d < pattern.size() && pattern[d] >= '0' && pattern[d] <= '9')
        ++d;
    if (d >= pattern.size() || pattern[d] != 'd')
        return numbers;
    const std::string flags = pattern.substr(pct + 1, d - pct - 1); // "06": zero-padded to 6
    const std::string prefix = pattern.substr(0, pct);
    const std::string suffix = pattern.substr(d + 1);
    if (suffix.find('/') != std::string::npos || flags.size() > 3)
        return numbers;
    const bool zeroPad = !flags.empty() && flags[0] == '0';
    const std::size_t width = flags.empty() ? 0 : std::stoul(flags);
    const std::size_t slash = prefix.rfind('/');
    const std::string dir = slash == std::string::npos ? "." : prefix.substr(0, slash + 1);
    const std::string stem = slash == std::string::npos ? prefix : prefix.substr(slash + 1);
    std::error_code ec;
    for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() <= stem.size() + suffix.size() || name.compare(0, stem.size(), stem) != 0 ||
            name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
            continue;
        const std::string field =
            name.substr(stem.size(), name.size() - stem.size() - suffix.size());
        const std::size_t first = field.find_first_not_of(zeroPad ? "" : " ");
        const std::string digits = first == std::string::npos ? "" : field.substr(first);
        if (digits.empty() || digits.size() > 15 ||
            !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
            continue;
        const long long n = std::stoll(digits);
        // The field must be exactly what the pattern makes of n (its padding rule).
        std::string made = std::to_string(n);
        if (made.size() < width)
            made.insert(0, width - made.size(), zeroPad ? '0' : ' ');
        if (made == field)
            numbers.push_back(n);
    }
    std::sort(numbers.begin(), numbers.end());
    return numbers;
}

long long nextImageNumber(const std::vector<long long> &numbers, long long last) noexcept
{
    const auto it = std::upper_bound(numbers.begin(), numbers.end(), last);
    return it == numbers.end() ? -1 : *it;
}

} // namespace depthtouch::media::detail

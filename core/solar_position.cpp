#include "core/solar_position.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace penumbra {

namespace {

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

double sinDeg(double degrees) {
    return std::sin(degrees / kDegreesPerRadian);
}

double cosDeg(double degrees) {
    return std::cos(degrees / kDegreesPerRadian);
}

double tanDeg(double degrees) {
    return std::tan(degrees / kDegreesPerRadian);
}

// x modulo `period`, in [0, period). A tiny negative remainder plus `period` rounds to `period`
// itself, which is 0 again.
double wrap(double x, double period) {
    const double wrapped = std::fmod(x, period);
    if (wrapped >= 0.0)
        return wrapped;
    return wrapped + period < period ? wrapped + period : 0.0;
}

// ---- Validation, shared by the parsers and solarPosition -------------------------------------

// A number as a person would write it in a message: 60, not 60.000000.
std::string formatNumber(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

constexpr double kMaxUtcOffsetHours = 14.0;  // UTC+14 (Kiribati) is the easternmost clock in use

bool isLeapYear(int year) {
    return (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
}

int daysInMonth(int year, int month) {
    constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    return month == 2 && isLeapYear(year) ? 29 : kDays[month - 1];
}

// What is wrong with `time`, or "" when nothing is.
std::string timeProblem(const LocalTime& time) {
    if (time.month < 1 || time.month > 12)
        return "month " + std::to_string(time.month) + " is not in 1-12";
    const int days = daysInMonth(time.year, time.month);
    if (time.day < 1 || time.day > days)
        return "day " + std::to_string(time.day) + " is not in 1-" + std::to_string(days) +
               " (month " + std::to_string(time.month) + " of " + std::to_string(time.year) + ")";
    if (time.hour < 0 || time.hour > 23)
        return "hour " + std::to_string(time.hour) + " is not in 0-23";
    if (time.minute < 0 || time.minute > 59)
        return "minute " + std::to_string(time.minute) + " is not in 0-59";
    if (!(time.second >= 0.0 && time.second < 60.0))
        return "second " + formatNumber(time.second) + " is not in [0, 60)";
    if (!(std::abs(time.utcOffsetHours) <= kMaxUtcOffsetHours))
        return "UTC offset " + formatNumber(time.utcOffsetHours) + " h is beyond +-14 h";
    return "";
}

// What is wrong with `site`, or "" when nothing is.
std::string siteProblem(const GeographicSite& site) {
    if (!(site.latitudeDegrees >= -90.0 && site.latitudeDegrees <= 90.0))
        return "latitude " + formatNumber(site.latitudeDegrees) + " is not in [-90, 90]";
    if (!(site.longitudeDegrees >= -180.0 && site.longitudeDegrees <= 180.0))
        return "longitude " + formatNumber(site.longitudeDegrees) + " is not in [-180, 180]";
    return "";
}

// ---- Parsing ----------------------------------------------------------------------------------

constexpr const char* kIsoForm =
    "YYYY-MM-DDThh:mm[:ss[.fff]] followed by Z, +hh:mm or +hhmm (- west of UTC), "
    "e.g. 2026-06-21T12:00+02:00";

constexpr const char* kSiteForm =
    "LAT,LON in decimal degrees (north and east positive), e.g. 39.742476,-105.1786";

// Reads an ISO 8601 time left to right; every refusal quotes the whole text and names the
// character where reading stopped.
class IsoTimeReader {
  public:
    explicit IsoTimeReader(const std::string& text) : text_(text) {}

    [[noreturn]] void refuse(const std::string& what) const {
        throw std::invalid_argument("time \"" + text_ + "\": " + what + "; the form is " +
                                    kIsoForm);
    }

    bool atEnd() const { return pos_ == text_.size(); }

    // Consumes `c` if it is next.
    bool accept(char c) {
        if (atEnd() || text_[pos_] != c)
            return false;
        ++pos_;
        return true;
    }

    void expect(char c, const char* where) {
        if (!accept(c))
            refuse(std::string("expected '") + c + "' " + where + " " + found());
    }

    // Exactly `count` decimal digits, the field `name`.
    int digits(int count, const char* name) {
        int value = 0;
        for (int i = 0; i < count; ++i) {
            if (atEnd() || text_[pos_] < '0' || text_[pos_] > '9')
                refuse(std::string("expected ") + std::to_string(count) + " digits for the " +
                       name + " " + found());
            value = 10 * value + (text_[pos_++] - '0');
        }
        return value;
    }

    // One or more digits after a decimal point, as a fraction in [0, 1).
    double fraction(const char* name) {
        double value = 0.0, scale = 0.1;
        const size_t start = pos_;
        while (!atEnd() && text_[pos_] >= '0' && text_[pos_] <= '9') {
            value += scale * (text_[pos_++] - '0');
            scale *= 0.1;
        }
        if (pos_ == start)
            refuse(std::string("expected the digits of the ") + name + " " + found());
        return value;
    }

    // "at character N, found 'x'" (1-based) or "at the end", for messages.
    std::string found() const {
        if (atEnd())
            return "at the end";
        return "at character " + std::to_string(pos_ + 1) + ", found '" + text_[pos_] + "'";
    }

  private:
    const std::string& text_;
    size_t pos_ = 0;
};

// The UTC offset after the time: "Z", or a sign, hh and mm with or without a colon.
double readUtcOffsetHours(IsoTimeReader& reader) {
    if (reader.accept('Z'))
        return 0.0;
    double sign = 1.0;
    if (reader.accept('-'))
        sign = -1.0;
    else if (!reader.accept('+'))
        reader.refuse("expected the UTC offset (Z, +hh:mm or -hh:mm) " + reader.found());
    const int hours = reader.digits(2, "offset hours");
    reader.accept(':');
    const int minutes = reader.digits(2, "offset minutes");
    if (minutes > 59)
        reader.refuse("offset minutes " + std::to_string(minutes) + " is not in 0-59");
    return sign * (hours + minutes / 60.0);
}

// One decimal number of a site, `field` naming it for messages.
double readDegrees(const std::string& text, std::string part, const char* field) {
    const auto first = part.find_first_not_of(' ');
    const auto last = part.find_last_not_of(' ');
    part = first == std::string::npos ? "" : part.substr(first, last - first + 1);
    // std::from_chars takes no leading '+', which a hand-written coordinate may have.
    const size_t start = !part.empty() && part[0] == '+' ? 1 : 0;
    double value = 0.0;
    const char* begin = part.data() + start;
    const char* end = part.data() + part.size();
    const auto [stop, error] = std::from_chars(begin, end, value);
    if (part.empty() || error != std::errc() || stop != end || !std::isfinite(value))
        throw std::invalid_argument("site \"" + text + "\": the " + field + " \"" + part +
                                    "\" is not a decimal number; the form is " + kSiteForm);
    return value;
}

// ---- The NOAA Solar Calculator ----------------------------------------------------------------
// Column by column as NOAA's spreadsheet (NOAA_Solar_Calculations_day.xls, documented at
// gml.noaa.gov/grad/solcalc/calcdetails.html) and main.js compute them; the equations are
// Meeus's (2nd ed., 1998), numbered below.

// Julian day at 0h of a Gregorian calendar date, Meeus eq. 7.1 (NOAA's getJD).
double julianDayAtMidnight(int year, int month, int day) {
    if (month <= 2) {
        year -= 1;
        month += 12;
    }
    const double A = std::floor(year / 100.0);
    const double B = 2.0 - A + std::floor(A / 4.0);
    return std::floor(365.25 * (year + 4716)) + std::floor(30.6001 * (month + 1)) + day + B -
           1524.5;
}

// What the sun's position needs of the date: the declination and the equation of time.
struct SunOfTheDay {
    double declinationDegrees;
    double equationOfTimeMinutes;  // apparent minus mean solar time
};

// T in Julian centuries from J2000.0 (Meeus eq. 25.1). NOAA evaluates it at UT rather than at
// dynamical time: Delta T (about a minute now) moves the sun by under 0.001 degrees.
SunOfTheDay sunOfTheDay(double T) {
    // Geometric mean longitude and mean anomaly of the sun, eccentricity of Earth's orbit
    // (Meeus eqs. 25.2, 25.3, 25.4).
    const double L0 = wrap(280.46646 + T * (36000.76983 + T * 0.0003032), 360.0);
    const double M = 357.52911 + T * (35999.05029 - 0.0001537 * T);
    const double e = 0.016708634 - T * (0.000042037 + 0.0000001267 * T);

    // Equation of the centre and the sun's true longitude (Meeus ch. 25).
    const double C = sinDeg(M) * (1.914602 - T * (0.004817 + 0.000014 * T)) +
                     sinDeg(2.0 * M) * (0.019993 - 0.000101 * T) + sinDeg(3.0 * M) * 0.000289;
    const double trueLongitude = L0 + C;

    // Apparent longitude, corrected for nutation and aberration through the longitude of the
    // Moon's ascending node Omega (Meeus ch. 25, "apparent longitude").
    const double omega = 125.04 - 1934.136 * T;
    const double lambda = trueLongitude - 0.00569 - 0.00478 * sinDeg(omega);

    // Mean obliquity of the ecliptic (Meeus eq. 22.2, 23°26'21.448" - 46.8150" T - ...) and its
    // correction for the apparent position (Meeus eq. 25.8).
    const double seconds = 21.448 - T * (46.8150 + T * (0.00059 - T * 0.001813));
    const double epsilon0 = 23.0 + (26.0 + seconds / 60.0) / 60.0;
    const double epsilon = epsilon0 + 0.00256 * cosDeg(omega);

    // Declination (Meeus eq. 25.7).
    const double declination = kDegreesPerRadian * std::asin(sinDeg(epsilon) * sinDeg(lambda));

    // Equation of time, Smart's series (Meeus eq. 28.3), in radians, then 4 minutes per degree.
    const double y = tanDeg(epsilon / 2.0) * tanDeg(epsilon / 2.0);
    const double E = y * sinDeg(2.0 * L0) - 2.0 * e * sinDeg(M) +
                     4.0 * e * y * sinDeg(M) * cosDeg(2.0 * L0) - 0.5 * y * y * sinDeg(4.0 * L0) -
                     1.25 * e * e * sinDeg(2.0 * M);
    return {declination, 4.0 * kDegreesPerRadian * E};
}

// NOAA's approximation of atmospheric refraction (degrees) at the true elevation `elevation`
// (degrees): the piecewise fit in arcseconds of calcdetails.html, "Atmospheric Refraction
// Effects", for a standard atmosphere (the same as NREL's SOLPOS at 1013 mb and 10 °C). Below
// -0.575° it has -20.774 as main.js does; the spreadsheet has -20.772.
double refractionDegrees(double elevation) {
    if (elevation > 85.0)
        return 0.0;
    const double t = tanDeg(elevation);
    double arcseconds = 0.0;
    if (elevation > 5.0)
        arcseconds = 58.1 / t - 0.07 / (t * t * t) + 0.000086 / (t * t * t * t * t);
    else if (elevation > -0.575)
        arcseconds =
            1735.0 +
            elevation * (-518.2 + elevation * (103.4 + elevation * (-12.79 + elevation * 0.711)));
    else
        arcseconds = -20.774 / t;
    return arcseconds / 3600.0;
}

}  // namespace

LocalTime parseIsoLocalTime(const std::string& text) {
    IsoTimeReader reader(text);
    LocalTime time;
    time.year = reader.digits(4, "year");
    reader.expect('-', "after the year");
    time.month = reader.digits(2, "month");
    reader.expect('-', "after the month");
    time.day = reader.digits(2, "day");
    reader.expect('T', "between the date and the time");
    time.hour = reader.digits(2, "hour");
    reader.expect(':', "after the hour");
    time.minute = reader.digits(2, "minute");
    time.second = 0.0;
    if (reader.accept(':')) {
        time.second = reader.digits(2, "second");
        if (reader.accept('.'))
            time.second += reader.fraction("second's fraction");
    }
    time.utcOffsetHours = readUtcOffsetHours(reader);
    if (!reader.atEnd())
        reader.refuse("unexpected text after the UTC offset " + reader.found());
    const std::string problem = timeProblem(time);
    if (!problem.empty())
        reader.refuse(problem);
    return time;
}

GeographicSite parseSite(const std::string& text) {
    const size_t comma = text.find(',');
    if (comma == std::string::npos || text.find(',', comma + 1) != std::string::npos)
        throw std::invalid_argument("site \"" + text +
                                    "\": expected exactly one comma between latitude and "
                                    "longitude; the form is " +
                                    kSiteForm);
    GeographicSite site;
    site.latitudeDegrees = readDegrees(text, text.substr(0, comma), "latitude");
    site.longitudeDegrees = readDegrees(text, text.substr(comma + 1), "longitude");
    const std::string problem = siteProblem(site);
    if (!problem.empty())
        throw std::invalid_argument("site \"" + text + "\": " + problem + "; the form is " +
                                    kSiteForm);
    return site;
}

SolarPosition solarPosition(const GeographicSite& site, const LocalTime& time) {
    for (const std::string& problem : {siteProblem(site), timeProblem(time)}) {
        if (!problem.empty())
            throw std::invalid_argument("solarPosition: " + problem);
    }

    // The instant in UT: the clock's minutes since its midnight, less its offset.
    const double clockMinutes = 60.0 * time.hour + time.minute + time.second / 60.0;
    const double utMinutes = clockMinutes - 60.0 * time.utcOffsetHours;
    const double jd = julianDayAtMidnight(time.year, time.month, time.day) + utMinutes / 1440.0;
    const SunOfTheDay sun = sunOfTheDay((jd - 2451545.0) / 36525.0);

    // True solar time (minutes) and the hour angle H, measured westward from the meridian: 4
    // minutes of time per degree of longitude (NOAA's "True Solar Time", "Hour Angle").
    const double trueSolarMinutes =
        wrap(utMinutes + sun.equationOfTimeMinutes + 4.0 * site.longitudeDegrees, 1440.0);
    const double H = trueSolarMinutes / 4.0 - 180.0;

    // Zenith angle from cos z = sin phi sin delta + cos phi cos delta cos H (Meeus eq. 13.6).
    const double phi = site.latitudeDegrees, delta = sun.declinationDegrees;
    const double cosZenith = sinDeg(phi) * sinDeg(delta) + cosDeg(phi) * cosDeg(delta) * cosDeg(H);
    const double trueZenith = kDegreesPerRadian * std::acos(std::clamp(cosZenith, -1.0, 1.0));

    // Azimuth from Meeus eq. 13.5 (measured westward from south; numerator and denominator
    // multiplied by cos delta), turned to north = 0 by adding 180. It is the angle NOAA's
    // acos form gives, but atan2 keeps the quadrant and holds at the poles, where NOAA's
    // denominator cos phi sin z vanishes.
    const double fromSouth =
        kDegreesPerRadian *
        std::atan2(sinDeg(H) * cosDeg(delta),
                   cosDeg(H) * cosDeg(delta) * sinDeg(phi) - sinDeg(delta) * cosDeg(phi));
    SolarPosition position;
    position.azimuthDegrees = wrap(fromSouth + 180.0, 360.0);
    position.zenithDegrees = trueZenith - refractionDegrees(90.0 - trueZenith);
    return position;
}

Vec3 sunDirection(const SolarPosition& position, double northDegrees) {
    // In the frame north = -Z, east = +X, up = +Y: azimuth A turns from north towards east,
    // elevation 90 - zenith lifts off the horizon.
    const double A = position.azimuthDegrees, z = position.zenithDegrees;
    const double x = sinDeg(z) * sinDeg(A), y = cosDeg(z), zAxis = -sinDeg(z) * cosDeg(A);
    // R_y(theta): (x, y, z) -> (x cos theta + z sin theta, y, -x sin theta + z cos theta).
    const double c = cosDeg(northDegrees), s = sinDeg(northDegrees);
    return Vec3(static_cast<float>(x * c + zAxis * s), static_cast<float>(y),
                static_cast<float>(-x * s + zAxis * c));
}

}  // namespace penumbra

// The sun's position in the sky for a place on Earth and a local clock time, for daylight: by the
// NOAA Solar Calculator (NOAA ESRL Global Monitoring Laboratory, the spreadsheet and JavaScript at
// gml.noaa.gov/grad/solcalc/), which evaluates the low-precision solar coordinates of Meeus,
// "Astronomical Algorithms" (2nd ed., 1998). Meeus gives these solar coordinates as good to
// 0.01 degree (ch. 25); NOAA calls its approximations very good for 1800-2100 and sufficient for
// -1000 to 3000.
//
// Angles are in degrees. Bad input (a malformed string, a field out of range) is refused with
// std::invalid_argument whose message quotes the input and says what form is expected.
#pragma once

#include "core/math.h"

#include <string>

namespace penumbra {

// A place on Earth: latitude in [-90, 90] (north positive), longitude in [-180, 180] (east
// positive), both in degrees (WGS 84, as any map gives them).
struct GeographicSite {
    double latitudeDegrees = 0.0;
    double longitudeDegrees = 0.0;
};

// A clock time in the proleptic Gregorian calendar and the offset of that clock from UTC (hours,
// east positive, within +-14): 12:00 at utcOffsetHours = 2 is 10:00 UTC. second is in [0, 60):
// leap seconds are not taken.
struct LocalTime {
    int year = 2000, month = 1, day = 1, hour = 0, minute = 0;
    double second = 0.0;
    double utcOffsetHours = 0.0;
};

// Parses an ISO 8601 local time with its offset, "YYYY-MM-DDThh:mm[:ss[.fff]]" followed by "Z",
// "+hh:mm" / "-hh:mm" or "+hhmm" / "-hhmm", e.g. "2026-06-21T12:00+02:00". The offset is
// required: a time without one names no instant.
LocalTime parseIsoLocalTime(const std::string& text);

// Parses "LAT,LON" in decimal degrees, e.g. "39.742476,-105.1786" (spaces around either number
// are allowed).
GeographicSite parseSite(const std::string& text);

// Where the sun is seen from a site: the zenith angle (0 overhead, 90 on the horizon, above 90
// below it) of the sun's centre, corrected for atmospheric refraction by NOAA's approximation (a
// standard atmosphere: no pressure or temperature), and the azimuth, clockwise from true north
// (east = 90), in [0, 360).
struct SolarPosition {
    double zenithDegrees = 0.0;
    double azimuthDegrees = 0.0;
};

// The sun's position at `site` and `time`. Throws std::invalid_argument for a site or a time whose
// fields are out of the ranges above (a day that its month does not have included).
SolarPosition solarPosition(const GeographicSite& site, const LocalTime& time);

// The unit world direction towards the sun, in scene axes: +Y up and, for northDegrees = 0, true
// north along -Z and east along +X. northDegrees turns north counter-clockwise seen from above:
// the direction for northDegrees = 0 is rotated about +Y by +northDegrees (the right-handed R_y,
// which turns +Z towards +X), so northDegrees = 90 puts north along -X.
Vec3 sunDirection(const SolarPosition& position, double northDegrees);

}  // namespace penumbra

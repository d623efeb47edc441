// The sun's position (core/solar_position.h) against published positions the code did not make:
// the worked example of NREL's Solar Position Algorithm and U.S. Naval Observatory altitude and
// azimuth tables; against the closed form of the noon zenith at the June solstice; the scene
// direction's axes; and the parsers' refusals.
#include "core/solar_position.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra {
namespace {

// The difference of two azimuths, in (-180, 180].
double azimuthDifference(double a, double b) {
    const double d = std::fmod(a - b, 360.0);
    return d > 180.0 ? d - 360.0 : (d <= -180.0 ? d + 360.0 : d);
}

TEST(SolarPosition, MatchesTheNrelSpaWorkedExample) {
    // Reda and Andreas 2004, "Solar position algorithm for solar radiation applications", Solar
    // Energy 76(5) 577-589, and NREL/TP-560-34302 (rev. 2008), the worked example of the
    // appendix: 2003-10-17 12:30:30 at UTC-7, latitude 39.742476, longitude -105.1786 (elevation
    // 1830.14 m, 820 mbar, 11 °C, Delta T 67 s): topocentric zenith 50.11162°, azimuth
    // 194.34024°. The two algorithms differ by less than the tolerance: SPA refracts for 820 mbar
    // and 11 °C, 0.0163° at this elevation (its eq. 42), NOAA for a standard atmosphere, 0.0193°
    // (0.0030° less zenith); SPA's topocentric parallax adds 0.0019° to its zenith; Meeus gives
    // the low-accuracy solar coordinates NOAA uses as good to 0.01° (ch. 25). Their sum, 0.015°,
    // is under 0.05°. Measured: zenith -0.0030°, azimuth +0.0023°.
    const SolarPosition position =
        solarPosition({39.742476, -105.1786}, parseIsoLocalTime("2003-10-17T12:30:30-07:00"));
    EXPECT_NEAR(position.zenithDegrees, 50.11162, 0.05);
    EXPECT_NEAR(azimuthDifference(position.azimuthDegrees, 194.34024), 0.0, 0.05);
}

struct PublishedPosition {
    GeographicSite site;
    const char* time;
    double altitudeDegrees;  // refracted, as printed
    double azimuthDegrees;
};

TEST(SolarPosition, MatchesUsnoAltitudeAzimuthTables) {
    // U.S. Naval Observatory, Astronomical Applications Department, "Altitude and Azimuth of the
    // Sun" (aa.usno.navy.mil/data/docs/AltAz.php): the altitude includes standard refraction, the
    // azimuth is from true north. Four tables of 2016, transcribed verbatim into the Vesper
    // project's tests (Harold Mills); every row with the sun at least 5° up (nearer the horizon
    // USNO's standard refraction and NOAA's fit part). The tables print 0.1°, so their rounding
    // alone is up to 0.05°: the tolerance adds the 0.01° to which Meeus (ch. 25) gives the solar
    // coordinates, which an error in position turns into 1 / sin(zenith) times as much azimuth.
    // Measured: at most 0.053° in altitude (0°N 0°E, 16:00 UT), 0.057° in azimuth (42°27'S
    // 76°30'E, 12:00 at UTC+4, zenith 32°, where the bound is 0.069°).
    constexpr double kRounding = 0.05, kSolarCoordinates = 0.01;
    const GeographicSite ithaca{42.45, -76.5};  // W 76°30', N 42°27', its clock at UTC-4
    const GeographicSite nullIsland{0.0, 0.0};
    const GeographicSite southEast{-42.45, 76.5};  // E 76°30', S 42°27', its clock at UTC+4
    const GeographicSite tropics{5.0, -5.0};       // W 5°, N 5°
    const std::vector<PublishedPosition> table = {
        {ithaca, "2016-02-17T09:55-04:00", 18.1, 126.6},
        {ithaca, "2016-02-17T11:54-04:00", 32.1, 155.0},
        {ithaca, "2016-02-17T13:53-04:00", 35.1, 189.9},
        {ithaca, "2016-02-17T15:52-04:00", 25.4, 221.8},
        {ithaca, "2016-02-17T17:51-04:00", 7.8, 246.0},
        {nullIsland, "2016-02-01T08:00Z", 25.4, 109.1},
        {nullIsland, "2016-02-01T10:00Z", 52.9, 119.4},
        {nullIsland, "2016-02-01T12:00Z", 72.5, 169.2},
        {nullIsland, "2016-02-01T14:00Z", 58.7, 235.4},
        {nullIsland, "2016-02-01T16:00Z", 31.7, 249.7},
        {southEast, "2016-02-17T06:00+04:00", 17.8, 90.5},
        {southEast, "2016-02-17T08:00+04:00", 39.4, 67.7},
        {southEast, "2016-02-17T10:00+04:00", 56.3, 31.0},
        {southEast, "2016-02-17T12:00+04:00", 57.7, 335.7},
        {southEast, "2016-02-17T14:00+04:00", 42.0, 296.2},
        {southEast, "2016-02-17T16:00+04:00", 20.7, 272.4},
        {tropics, "2016-12-20T08:00Z", 21.1, 117.5},
        {tropics, "2016-12-20T10:00Z", 46.0, 131.7},
        {tropics, "2016-12-20T12:00Z", 61.2, 171.5},
        {tropics, "2016-12-20T14:00Z", 52.2, 220.2},
        {tropics, "2016-12-20T16:00Z", 28.9, 239.7},
    };
    for (const PublishedPosition& row : table) {
        SCOPED_TRACE(std::string(row.time) + " at " + std::to_string(row.site.latitudeDegrees) +
                     ", " + std::to_string(row.site.longitudeDegrees));
        const SolarPosition position = solarPosition(row.site, parseIsoLocalTime(row.time));
        const double zenith = 90.0 - row.altitudeDegrees;
        EXPECT_NEAR(position.zenithDegrees, zenith, kRounding + kSolarCoordinates);
        const double sinZenith = std::sin(zenith * std::numbers::pi / 180.0);
        EXPECT_NEAR(azimuthDifference(position.azimuthDegrees, row.azimuthDegrees), 0.0,
                    kRounding + kSolarCoordinates / sinZenith);
    }
}

TEST(SolarPosition, NoonZenithAtTheJuneSolsticeIsTheLatitudeLessTheObliquity) {
    // On the June solstice (2026-06-21, about 08:24 UT) the declination is the obliquity of the
    // ecliptic, 23.44°, and changes by under 0.003° in a day; at the meridian the zenith is
    // |latitude - declination|. The smallest zenith of a minute-by-minute scan is that within
    // 0.05°: refraction lowers it by at most 0.022° at these latitudes (at latitude -30°,
    // elevation 36.6°), and within half a minute of the meridian the zenith changes by under
    // 0.001°. The sun is then due south of sites north of the tropic and due north of those south
    // of it; there the azimuth turns by cos(declination) / sin(zenith) times 0.25° a minute, at
    // most 0.58° (at the equator), so half a minute from the meridian it is off by under 0.3°.
    constexpr double kObliquity = 23.44;
    struct Site {
        GeographicSite site;
        const char* offset;
    };
    for (const Site& s : {Site{{60.0, 10.75}, "+02:00"}, Site{{51.5, 0.0}, "Z"},
                          Site{{0.0, -78.5}, "-05:00"}, Site{{-30.0, 151.2}, "+10:00"}}) {
        SCOPED_TRACE(std::to_string(s.site.latitudeDegrees));
        SolarPosition noon{180.0, 0.0};
        for (int minute = 0; minute < 24 * 60; ++minute) {
            const LocalTime time = parseIsoLocalTime(
                "2026-06-21T" + std::string(minute / 60 < 10 ? "0" : "") +
                std::to_string(minute / 60) + ":" + (minute % 60 < 10 ? "0" : "") +
                std::to_string(minute % 60) + s.offset);
            const SolarPosition position = solarPosition(s.site, time);
            if (position.zenithDegrees < noon.zenithDegrees)
                noon = position;
        }
        EXPECT_NEAR(noon.zenithDegrees, std::abs(s.site.latitudeDegrees - kObliquity), 0.05);
        const double expectedAzimuth = s.site.latitudeDegrees > kObliquity ? 180.0 : 0.0;
        EXPECT_NEAR(azimuthDifference(noon.azimuthDegrees, expectedAzimuth), 0.0, 0.3);
    }
}

TEST(SolarPosition, RefusesFieldsOutOfRange) {
    LocalTime april31;
    april31.year = 2026;
    april31.month = 4;
    april31.day = 31;
    EXPECT_THROW(solarPosition({0.0, 0.0}, april31), std::invalid_argument);
    EXPECT_THROW(solarPosition({90.5, 0.0}, LocalTime{}), std::invalid_argument);
    LocalTime farEast;
    farEast.utcOffsetHours = 14.5;
    EXPECT_THROW(solarPosition({0.0, 0.0}, farEast), std::invalid_argument);
}

void expectVec3Near(const Vec3& actual, const Vec3& expected) {
    EXPECT_NEAR(actual.x, expected.x, 1e-6f);
    EXPECT_NEAR(actual.y, expected.y, 1e-6f);
    EXPECT_NEAR(actual.z, expected.z, 1e-6f);
}

TEST(SunDirection, FollowsTheSceneAxes) {
    // North 0: north is -Z, east +X, up +Y.
    expectVec3Near(sunDirection({90.0, 90.0}, 0.0), Vec3(1, 0, 0));
    expectVec3Near(sunDirection({90.0, 0.0}, 0.0), Vec3(0, 0, -1));
    expectVec3Near(sunDirection({90.0, 180.0}, 0.0), Vec3(0, 0, 1));
    expectVec3Near(sunDirection({0.0, 123.0}, 0.0), Vec3(0, 1, 0));
    // Zenith 60° due south: cos 60° up, sin 60° towards +Z.
    expectVec3Near(sunDirection({60.0, 180.0}, 0.0), Vec3(0, 0.5f, std::sqrt(3.0f) / 2.0f));
}

TEST(SunDirection, NorthTurnsCounterClockwiseSeenFromAbove) {
    // R_y(90°) takes north (-Z) to -X and east (+X) to -Z: seen from +Y, with +X to the right
    // and -Z up, north turns from up to the left.
    expectVec3Near(sunDirection({90.0, 0.0}, 90.0), Vec3(-1, 0, 0));
    expectVec3Near(sunDirection({90.0, 90.0}, 90.0), Vec3(0, 0, -1));
    // R_y(30°) of east: (cos 30°, 0, -sin 30°).
    expectVec3Near(sunDirection({90.0, 90.0}, 30.0), Vec3(std::sqrt(3.0f) / 2.0f, 0, -0.5f));
    // The zenith stays put, and the result is a unit vector.
    expectVec3Near(sunDirection({0.0, 45.0}, 77.0), Vec3(0, 1, 0));
    EXPECT_NEAR(glm::length(sunDirection({37.0, 211.0}, -123.0)), 1.0f, 1e-6f);
}

TEST(ParseIsoLocalTime, ReadsTheFieldsAndTheOffset) {
    const LocalTime t = parseIsoLocalTime("2026-06-21T12:00+02:00");
    EXPECT_EQ(t.year, 2026);
    EXPECT_EQ(t.month, 6);
    EXPECT_EQ(t.day, 21);
    EXPECT_EQ(t.hour, 12);
    EXPECT_EQ(t.minute, 0);
    EXPECT_EQ(t.second, 0.0);
    EXPECT_EQ(t.utcOffsetHours, 2.0);

    const LocalTime fraction = parseIsoLocalTime("2003-10-17T12:30:30.25Z");
    EXPECT_EQ(fraction.second, 30.25);
    EXPECT_EQ(fraction.utcOffsetHours, 0.0);
    EXPECT_EQ(parseIsoLocalTime("2026-01-05T06:07-0330").utcOffsetHours, -3.5);
    EXPECT_EQ(parseIsoLocalTime("2026-01-05T06:07+05:45").utcOffsetHours, 5.75);
    EXPECT_EQ(parseIsoLocalTime("2026-01-05T06:07+14:00").utcOffsetHours, 14.0);
    // Leap days: every fourth year, but not centuries other than every fourth.
    EXPECT_EQ(parseIsoLocalTime("2024-02-29T00:00Z").day, 29);
    EXPECT_EQ(parseIsoLocalTime("2000-02-29T00:00Z").day, 29);
}

TEST(ParseIsoLocalTime, RefusesBadTextQuotingIt) {
    for (const std::string text : {
             "",
             "2026-06-21T12:00",        // no offset
             "2026-06-21 12:00+02:00",  // no 'T'
             "26-06-21T12:00Z",         // two-digit year
             "2026-6-21T12:00Z",        // one-digit month
             "2026-13-01T00:00Z",       // month 13
             "2026-04-31T00:00Z",       // April has 30 days
             "2023-02-29T00:00Z",       // not a leap year
             "1900-02-29T00:00Z",       // a century that is not a leap year
             "2026-06-21T24:00Z",       // hour 24
             "2026-06-21T12:60Z",       // minute 60
             "2026-06-21T12:00:60Z",    // leap seconds are not taken
             "2026-06-21T12:00:5Z",     // one-digit second
             "2026-06-21T12:00:05.Z",   // a point without digits
             "2026-06-21T12:00+02",     // offset without minutes
             "2026-06-21T12:00+02:60",  // offset minutes 60
             "2026-06-21T12:00+15:00",  // beyond +14 h
             "2026-06-21T12:00-14:30",  // beyond -14 h
             "2026-06-21T12:00+02:00x"  // trailing text
         }) {
        SCOPED_TRACE(text);
        try {
            parseIsoLocalTime(text);
            ADD_FAILURE() << "accepted";
        } catch (const std::invalid_argument& error) {
            const std::string message = error.what();
            EXPECT_NE(message.find("\"" + text + "\""), std::string::npos) << message;
            EXPECT_NE(message.find("YYYY-MM-DDThh:mm"), std::string::npos) << message;
        }
    }
}

TEST(ParseSite, ReadsLatitudeThenLongitude) {
    const GeographicSite golden = parseSite("39.742476,-105.1786");
    EXPECT_EQ(golden.latitudeDegrees, 39.742476);
    EXPECT_EQ(golden.longitudeDegrees, -105.1786);
    const GeographicSite spaced = parseSite(" -33.9 , +151.2 ");
    EXPECT_EQ(spaced.latitudeDegrees, -33.9);
    EXPECT_EQ(spaced.longitudeDegrees, 151.2);
    EXPECT_EQ(parseSite("90,-180").latitudeDegrees, 90.0);
}

TEST(ParseSite, RefusesBadTextQuotingIt) {
    for (const std::string text : {"", "39.7", "39.7;-105.2", "1,2,3", "north,5", "5,", "91,0",
                                   "-90.5,0", "0,180.5", "nan,0", "0,inf", "1e3,0", "5 5,0"}) {
        SCOPED_TRACE(text);
        try {
            parseSite(text);
            ADD_FAILURE() << "accepted";
        } catch (const std::invalid_argument& error) {
            const std::string message = error.what();
            EXPECT_NE(message.find("\"" + text + "\""), std::string::npos) << message;
            EXPECT_NE(message.find("LAT,LON"), std::string::npos) << message;
        }
    }
}

}  // namespace
}  // namespace penumbra

//! An instant of time, parsed from ISO 8601 with an explicit UTC offset.
//!
//! The accepted form is the extended one of RFC 3339 with seconds optional:
//!
//! ```text
//!   YYYY-MM-DDThh:mm[:ss[.f…]](Z | ±hh:mm | ±hhmm | ±hh)
//! ```
//!
//! `t` may stand for `T` and `z` for `Z`, a comma for the decimal point. A
//! leap second (ss = 60) is counted as a plain second, landing on the next
//! minute's 00, as POSIX time does. Dates are proleptic Gregorian.
//!
//! # References
//! - ISO 8601-1:2019, *Date and time — Representations for information
//!   interchange*; RFC 3339, *Date and Time on the Internet: Timestamps*.
//! - H. Hinnant, "chrono-Compatible Low-Level Date Algorithms"
//!   (`days_from_civil`), 2013.

use std::str::FromStr;

/// Seconds in a day.
const DAY: f64 = 86_400.0;
/// The Julian day of the Unix epoch, 1970-01-01T00:00Z.
const UNIX_EPOCH_JULIAN_DAY: f64 = 2_440_587.5;
/// The largest UTC offset in use, minutes (Kiribati's +14:00).
const MAX_OFFSET_MINUTES: i64 = 14 * 60;

/// An instant parsed from ISO 8601 with a UTC offset, e.g.
/// "2026-06-21T12:00:00+02:00" or "2026-06-21T10:00Z": seconds optional,
/// fractional seconds allowed, the offset required (see the module docs).
///
/// Held as seconds since 1970-01-01T00:00Z (UTC, leap seconds not counted),
/// which as an f64 resolves better than a microsecond for centuries around.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct Instant {
    unix_seconds: f64,
}

impl Instant {
    /// The instant `unix_seconds` after 1970-01-01T00:00Z.
    #[must_use]
    pub fn from_unix_seconds(unix_seconds: f64) -> Instant {
        Instant { unix_seconds }
    }

    /// Seconds since 1970-01-01T00:00Z.
    #[must_use]
    pub fn unix_seconds(self) -> f64 {
        self.unix_seconds
    }

    /// The Julian day (UT): JD = unix seconds / 86 400 + 2 440 587.5.
    #[must_use]
    pub fn julian_day(self) -> f64 {
        self.unix_seconds / DAY + UNIX_EPOCH_JULIAN_DAY
    }

    /// Minutes since the last UTC midnight, in [0, 1440).
    #[must_use]
    pub fn utc_minutes_of_day(self) -> f64 {
        self.unix_seconds.rem_euclid(DAY) / 60.0
    }
}

/// Days from 1970-01-01 to the proleptic Gregorian `year`-`month`-`day`
/// (Hinnant's `days_from_civil`).
fn days_from_civil(year: i64, month: i64, day: i64) -> i64 {
    let year = if month <= 2 { year - 1 } else { year };
    let era = year.div_euclid(400);
    let year_of_era = year - era * 400;
    let day_of_year = (153 * (month + if month > 2 { -3 } else { 9 }) + 2) / 5 + day - 1;
    let day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
    era * 146_097 + day_of_era - 719_468
}

/// Days in `month` of `year` (Gregorian leap years).
fn days_in_month(year: i64, month: i64) -> i64 {
    match month {
        2 if year % 4 == 0 && (year % 100 != 0 || year % 400 == 0) => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// A reading position in the text being parsed.
struct Cursor<'a> {
    text: &'a str,
    at: usize,
}

impl Cursor<'_> {
    fn peek(&self) -> Option<u8> {
        self.text.as_bytes().get(self.at).copied()
    }

    /// The error for a missing `what` at the current position.
    fn expected(&self, what: &str) -> String {
        let found = match self
            .text
            .get(self.at..)
            .and_then(|rest| rest.chars().next())
        {
            Some(c) => format!("'{c}'"),
            None => "the end".to_string(),
        };
        format!(
            "\"{}\" is not an ISO 8601 instant: expected {what} at position {}, found {found}",
            self.text,
            self.at + 1
        )
    }

    /// Exactly `count` ASCII digits, as a number.
    fn digits(&mut self, count: usize, what: &str) -> Result<i64, String> {
        let mut value = 0;
        for _ in 0..count {
            match self.peek() {
                Some(b) if b.is_ascii_digit() => value = value * 10 + i64::from(b - b'0'),
                _ => return Err(self.expected(what)),
            }
            self.at += 1;
        }
        Ok(value)
    }

    /// One of `bytes`, which one.
    fn one_of(&mut self, bytes: &[u8], what: &str) -> Result<u8, String> {
        match self.peek() {
            Some(b) if bytes.contains(&b) => {
                self.at += 1;
                Ok(b)
            }
            _ => Err(self.expected(what)),
        }
    }

    /// A decimal fraction after its point: at least one digit.
    fn fraction(&mut self) -> Result<f64, String> {
        let (mut value, mut scale) = (0.0, 0.1);
        let start = self.at;
        while let Some(b) = self.peek().filter(u8::is_ascii_digit) {
            value += f64::from(b - b'0') * scale;
            scale *= 0.1;
            self.at += 1;
        }
        if self.at == start {
            Err(self.expected("a digit of the fraction of a second"))
        } else {
            Ok(value)
        }
    }
}

/// The fields of an ISO 8601 instant as written.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Fields {
    year: i64,
    month: i64,
    day: i64,
    hour: i64,
    minute: i64,
    second: f64,
    offset_minutes: i64,
}

/// The fields of `text`, syntax checked (ranges are not).
fn read_fields(text: &str) -> Result<Fields, String> {
    let mut c = Cursor { text, at: 0 };
    let year = c.digits(4, "a four-digit year")?;
    c.one_of(b"-", "'-' after the year")?;
    let month = c.digits(2, "a two-digit month")?;
    c.one_of(b"-", "'-' after the month")?;
    let day = c.digits(2, "a two-digit day")?;
    c.one_of(b"Tt", "'T' between the date and the time")?;
    let hour = c.digits(2, "a two-digit hour")?;
    c.one_of(b":", "':' after the hour")?;
    let minute = c.digits(2, "two-digit minutes")?;
    let mut second = 0.0;
    if c.peek() == Some(b':') {
        c.at += 1;
        second = c.digits(2, "two-digit seconds")? as f64;
        if matches!(c.peek(), Some(b'.' | b',')) {
            c.at += 1;
            second += c.fraction()?;
        }
    }
    let offset_minutes = read_offset(&mut c)?;
    if c.at < text.len() {
        return Err(c.expected("the end after the UTC offset"));
    }
    Ok(Fields {
        year,
        month,
        day,
        hour,
        minute,
        second,
        offset_minutes,
    })
}

/// The UTC offset in minutes: Z, or ±hh[[:]mm]; Err when there is none.
fn read_offset(c: &mut Cursor) -> Result<i64, String> {
    let what = "a UTC offset ('Z', '+hh:mm' or '-hh:mm'): the time zone must be explicit";
    let sign = match c.one_of(b"Zz+-", what)? {
        b'+' => 1,
        b'-' => -1,
        _ => return Ok(0),
    };
    let hours = c.digits(2, "a two-digit offset hour")?;
    if c.peek() == Some(b':') {
        c.at += 1;
    }
    let minutes = if c.peek().is_some_and(|b| b.is_ascii_digit()) {
        c.digits(2, "two-digit offset minutes")?
    } else {
        0
    };
    if minutes > 59 {
        return Err(format!(
            "\"{}\": offset minutes {minutes} are not in 0–59",
            c.text
        ));
    }
    let total = hours * 60 + minutes;
    if total > MAX_OFFSET_MINUTES {
        return Err(format!(
            "\"{}\": the UTC offset {hours:02}:{minutes:02} is beyond ±14:00",
            c.text
        ));
    }
    Ok(sign * total)
}

/// Err naming the first field out of its range.
fn check_ranges(text: &str, f: &Fields) -> Result<(), String> {
    if !(1..=12).contains(&f.month) {
        return Err(format!("\"{text}\": month {} is not in 1–12", f.month));
    }
    let last = days_in_month(f.year, f.month);
    if !(1..=last).contains(&f.day) {
        return Err(format!(
            "\"{text}\": day {} is not in 1–{last} for {:04}-{:02}",
            f.day, f.year, f.month
        ));
    }
    if f.hour > 23 {
        return Err(format!("\"{text}\": hour {} is not in 0–23", f.hour));
    }
    if f.minute > 59 {
        return Err(format!("\"{text}\": minute {} is not in 0–59", f.minute));
    }
    if f.second.is_nan() || f.second >= 61.0 {
        return Err(format!("\"{text}\": second {} is not below 61", f.second));
    }
    Ok(())
}

impl FromStr for Instant {
    type Err = String;

    /// Parses `YYYY-MM-DDThh:mm[:ss[.f…]]` followed by `Z` or `±hh:mm`
    /// (see the module docs); Err saying what is wrong, and where, otherwise.
    fn from_str(text: &str) -> Result<Instant, String> {
        let f = read_fields(text)?;
        check_ranges(text, &f)?;
        let days = days_from_civil(f.year, f.month, f.day);
        let whole_minutes = days * 1440 + f.hour * 60 + f.minute - f.offset_minutes;
        Ok(Instant {
            unix_seconds: whole_minutes as f64 * 60.0 + f.second,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Instant {
        text.parse().unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn accepted_forms() {
        assert_eq!(parse("1970-01-01T00:00Z").unix_seconds(), 0.0);
        assert_eq!(parse("2000-01-01T12:00:00Z").julian_day(), 2_451_545.0);
        let noon = parse("2026-06-21T12:00:00+02:00");
        assert_eq!(noon, parse("2026-06-21T10:00Z"));
        assert_eq!(noon, parse("2026-06-21t10:00:00z"));
        assert_eq!(noon, parse("2026-06-21T05:30-0430"));
        assert_eq!(noon, parse("2026-06-21T11:00+01"));
        assert_eq!(
            parse("2026-06-21T10:00:00.25Z").unix_seconds() - noon.unix_seconds(),
            0.25
        );
        assert_eq!(
            parse("2026-06-21T10:00:00,5Z").unix_seconds() - noon.unix_seconds(),
            0.5
        );
        // A leap second lands on the next minute's 00.
        assert_eq!(parse("2016-12-31T23:59:60Z"), parse("2017-01-01T00:00:00Z"));
        assert_eq!(
            parse("2024-02-29T00:00+14:00").unix_seconds(),
            parse("2024-02-28T10:00Z").unix_seconds()
        );
        // NREL SPA's example: 2003-10-17 12:30:30 at UTC−7 is JD 2452930.312847.
        assert!((parse("2003-10-17T12:30:30-07:00").julian_day() - 2_452_930.312_847).abs() < 1e-6);
        assert_eq!(parse("1999-12-31T23:00:00-01:00").utc_minutes_of_day(), 0.0);
        assert_eq!(parse("1969-12-31T18:00Z").utc_minutes_of_day(), 1080.0);
    }

    #[test]
    fn refused_forms_say_what_is_wrong() {
        let cases = [
            ("2026-06-21T12:00:00", "time zone must be explicit"),
            ("2026-06-21T12:00", "time zone must be explicit"),
            ("2026-06-21", "'T'"),
            ("", "four-digit year"),
            ("26-06-21T12:00Z", "four-digit year"),
            ("2026-6-21T12:00Z", "two-digit month"),
            ("2026-13-01T12:00Z", "month 13"),
            ("2026-00-01T12:00Z", "month 0"),
            ("2026-02-29T12:00Z", "day 29 is not in 1–28"),
            ("2100-02-29T12:00Z", "day 29 is not in 1–28"),
            ("2026-04-31T12:00Z", "day 31 is not in 1–30"),
            ("2026-01-00T12:00Z", "day 0"),
            ("2026-06-21T24:00Z", "hour 24"),
            ("2026-06-21T12:60Z", "minute 60"),
            ("2026-06-21T12:00:61Z", "second 61"),
            ("2026-06-21T12:00:99Z", "second 99"),
            ("2026-06-21T12:00:00.Z", "fraction"),
            ("2026-06-21T12:00+14:30", "beyond ±14:00"),
            ("2026-06-21T12:00-15:00", "beyond ±14:00"),
            ("2026-06-21T12:00+02:75", "offset minutes 75"),
            ("2026-06-21T12:00+2", "two-digit offset hour"),
            ("2026-06-21T12:00Z ", "the end"),
            ("2026-06-21T12:00ZZ", "the end"),
            ("2026-06-21 12:00Z", "'T'"),
            ("２026-06-21T12:00Z", "four-digit year"),
        ];
        for (text, wanted) in cases {
            match text.parse::<Instant>() {
                Ok(i) => panic!("{text:?} parsed as {i:?}"),
                Err(e) => assert!(e.contains(wanted), "{text:?}: {e:?} lacks {wanted:?}"),
            }
        }
        assert!(parse("2024-02-29T12:00Z").unix_seconds() > 0.0);
        assert!(parse("2000-02-29T12:00Z").unix_seconds() > 0.0);
    }

    #[test]
    fn days_from_civil_counts_from_the_epoch() {
        assert_eq!(days_from_civil(1970, 1, 1), 0);
        assert_eq!(days_from_civil(2000, 3, 1), 11_017);
        assert_eq!(days_from_civil(1969, 12, 31), -1);
        assert_eq!(days_from_civil(1600, 1, 1), -135_140);
    }
}

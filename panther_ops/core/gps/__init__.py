"""GPS: NMEA decoding, the nmea-gps service / launch argument, the RUTX11's NMEA forwarding."""

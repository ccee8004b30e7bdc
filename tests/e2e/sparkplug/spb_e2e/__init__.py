"""The Sparkplug B end-to-end tests' own library (tests/e2e/sparkplug/*_test.py): a mosquitto of
the test's own, an observer that records every message, the gateway and its simulator, an
independent payload decoder, and a reader of the store's files. Nothing here shares code with the
gateway: the payloads are decoded by protoc's Python output of sparkplug/sparkplug_b.proto
(Debian's python3-protobuf), the store's files by their layout as store/record_frame.h and
docs/northbound.md ("The store") describe it."""

"""What a read-back of a flashed device means: identical, or the first byte that differs."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Verdict:
    """The device's first ``length`` bytes against the image."""

    device: str
    length: int
    image_sha256: str
    device_sha256: str
    first_difference: int | None
    seconds: float

    @property
    def ok(self) -> bool:
        return self.image_sha256 == self.device_sha256 and self.first_difference is None

    @property
    def message(self) -> str:
        if self.ok:
            return f"{self.device}: {self.length} bytes identical to the image (sha256 {self.device_sha256})"
        where = (
            f"first difference at byte {self.first_difference} (0x{self.first_difference:x})"
            if self.first_difference is not None else "no differing byte found on a second read"
        )
        return (f"{self.device}: differs from the image: {where}; "
                f"sha256 read back {self.device_sha256}, image {self.image_sha256}")

    def to_json(self) -> dict[str, Any]:
        return {
            "ok": self.ok, "device": self.device, "bytes": self.length, "image_sha256": self.image_sha256,
            "device_sha256": self.device_sha256, "first_difference": self.first_difference,
            "seconds": round(self.seconds, 3),
            "mib_per_s": round(self.length / (1 << 20) / self.seconds, 1) if self.seconds > 0 else None,
        }


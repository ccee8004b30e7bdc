#include "config/machine_checks.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <openssl/bio.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <pwd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fmt/format.h>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace tiltgate {

namespace {

std::optional<std::string> missing_user(const std::string& name) {
  if (name.empty()) return std::nullopt;
  std::vector<char> buffer(16384);
  passwd entry{};
  passwd* found = nullptr;
  const int error = ::getpwnam_r(name.c_str(), &entry, buffer.data(), buffer.size(), &found);
  if (found != nullptr) return std::nullopt;
  if (error != 0)
    return fmt::format("user \"{}\" cannot be looked up: {}", name, std::strerror(error));
  return fmt::format("no user \"{}\" on this machine: the gateway could not start as it "
                     "(create it, e.g. useradd --system {}, or name another)",
                     name, name);
}

// Binds a socket to the address on a port the kernel picks, and lets it go: the one test that
// agrees with what the listener will meet (an address of this machine, IPv6 present).
std::optional<std::string> address_not_here(const std::string& address) {
  sockaddr_storage storage{};
  socklen_t length = 0;
  auto* v4 = reinterpret_cast<sockaddr_in*>(&storage);
  auto* v6 = reinterpret_cast<sockaddr_in6*>(&storage);
  if (::inet_pton(AF_INET, address.c_str(), &v4->sin_addr) == 1) {
    v4->sin_family = AF_INET;
    length = sizeof(sockaddr_in);
  } else if (::inet_pton(AF_INET6, address.c_str(), &v6->sin6_addr) == 1) {
    v6->sin6_family = AF_INET6;
    length = sizeof(sockaddr_in6);
  } else {
    return std::nullopt;  // the loader reports it
  }
  const int fd = ::socket(storage.ss_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return fmt::format("\"{}\": {}", address, std::strerror(errno));
  const int bound = ::bind(fd, reinterpret_cast<sockaddr*>(&storage), length);
  const int error = errno;
  ::close(fd);
  if (bound == 0) return std::nullopt;
  if (error == EADDRNOTAVAIL)
    return fmt::format("no interface of this machine has the address {}: nothing could connect "
                       "(\"0.0.0.0\" serves every address, \"127.0.0.1\" this machine only)",
                       address);
  return fmt::format("cannot serve on {}: {}", address, std::strerror(error));
}

struct BioFree {
  void operator()(BIO* bio) const { BIO_free(bio); }
};
struct X509Free {
  void operator()(X509* x) const { X509_free(x); }
};
struct KeyFree {
  void operator()(EVP_PKEY* key) const { EVP_PKEY_free(key); }
};

std::unique_ptr<BIO, BioFree> memory_of(const std::string& pem) {
  return std::unique_ptr<BIO, BioFree>(BIO_new_mem_buf(pem.data(), int(pem.size())));
}

// No passphrase is asked for: an encrypted key cannot be served unattended.
int no_passphrase(char*, int, int, void*) { return 0; }

std::unique_ptr<X509, X509Free> first_certificate(const std::string& pem) {
  auto bio = memory_of(pem);
  return std::unique_ptr<X509, X509Free>(
      bio ? PEM_read_bio_X509(bio.get(), nullptr, no_passphrase, nullptr) : nullptr);
}

// What is wrong with a certificate file and its key file, in words that quote neither.
std::optional<std::string> pair_error(const std::string& cert_file, const std::string& cert_pem,
                                      const std::string& key_file, const std::string& key_pem) {
  auto certificate = first_certificate(cert_pem);
  if (!certificate) return fmt::format("{} holds no PEM certificate", cert_file);
  auto bio = memory_of(key_pem);
  std::unique_ptr<EVP_PKEY, KeyFree> key(
      bio ? PEM_read_bio_PrivateKey(bio.get(), nullptr, no_passphrase, nullptr) : nullptr);
  if (!key) return fmt::format("{} holds no unencrypted PEM private key", key_file);
  if (X509_check_private_key(certificate.get(), key.get()) != 1)
    return fmt::format("the key in {} is not the key of the certificate in {}", key_file,
                       cert_file);
  return std::nullopt;
}

}  // namespace

ConfigErrors check_on_this_machine(const Config& config) {
  ConfigErrors errors;
  const auto add = [&](std::string key, std::optional<std::string> problem) {
    if (problem)
      errors.push_back(FileError{config.path, 0, 0, std::move(key), std::move(*problem)});
  };
  add("server.user", missing_user(config.server.user));
  add("server.listen", address_not_here(config.server.listen));
  if (config.http.enabled) add("http.listen", address_not_here(config.http.listen));
  if (!config.http.tls_cert_pem.empty())
    add("http.tls_cert_file", pair_error(config.http.tls_cert_file, config.http.tls_cert_pem,
                                         config.http.tls_key_file, config.http.tls_key_pem));
  if (const auto& tls = config.server.tls) {
    add("server.tls", pair_error(tls->cert_file, tls->cert_pem, tls->key_file, tls->key_pem));
    if (!first_certificate(tls->ca_pem))
      add("server.tls", fmt::format("{} holds no PEM certificate (the clients' CA)", tls->ca_file));
  }
  return errors;
}

Expected<Config, ConfigErrors> checked_on_this_machine(Expected<Config, ConfigErrors> loaded) {
  if (!loaded) return loaded;
  ConfigErrors errors = check_on_this_machine(*loaded);
  if (!errors.empty()) return Unexpected{std::move(errors)};
  return loaded;
}

}  // namespace tiltgate

// A Modbus/TCP Security client's certificate (modbus_tcp/client_certificate.h): its subject in
// one RFC 2253 line and the role of its RoleOID extension, from certificates made here with
// OpenSSL and read back from PEM, as the server gets them from the handshake.
#include <doctest/doctest.h>

#include <openssl/evp.h>
#include <openssl/objects.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "modbus_tcp/client_certificate.h"

using namespace tiltgate;

namespace {

struct X509Free {
  void operator()(X509* x) const { X509_free(x); }
};
using Certificate = std::unique_ptr<X509, X509Free>;

// The DER of an ASN.1 string of `type` (V_ASN1_UTF8STRING, V_ASN1_IA5STRING) holding `text`.
std::string der_string(int type, std::string_view text) {
  ASN1_STRING* s = ASN1_STRING_type_new(type);
  ASN1_STRING_set(s, text.data(), int(text.size()));
  ASN1_TYPE* any = ASN1_TYPE_new();
  ASN1_TYPE_set(any, type, s);  // takes s
  unsigned char* der = nullptr;
  const int size = i2d_ASN1_TYPE(any, &der);
  REQUIRE(size > 0);
  std::string out(reinterpret_cast<const char*>(der), std::size_t(size));
  OPENSSL_free(der);
  ASN1_TYPE_free(any);
  return out;
}

// A self-signed certificate for O=Plant, CN=plc-1, with the role extension holding
// `extension` (DER) when given, written to PEM and read back.
Certificate make_certificate(std::optional<std::string> extension) {
  EVP_PKEY* key = EVP_EC_gen("P-256");
  REQUIRE(key != nullptr);
  X509* x = X509_new();
  X509_set_version(x, 2);
  ASN1_INTEGER_set(X509_get_serialNumber(x), 1);
  X509_gmtime_adj(X509_getm_notBefore(x), 0);
  X509_gmtime_adj(X509_getm_notAfter(x), 3600);
  X509_set_pubkey(x, key);
  X509_NAME* name = X509_get_subject_name(x);
  X509_NAME_add_entry_by_txt(name, "O", MBSTRING_ASC,
                             reinterpret_cast<const unsigned char*>("Plant"), -1, -1, 0);
  X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_ASC,
                             reinterpret_cast<const unsigned char*>("plc-1"), -1, -1, 0);
  X509_set_issuer_name(x, name);
  if (extension) {
    ASN1_OBJECT* oid = OBJ_txt2obj(std::string(kModbusRoleOid).c_str(), 1);
    ASN1_OCTET_STRING* data = ASN1_OCTET_STRING_new();
    ASN1_OCTET_STRING_set(data, reinterpret_cast<const unsigned char*>(extension->data()),
                          int(extension->size()));
    X509_EXTENSION* made = X509_EXTENSION_create_by_OBJ(nullptr, oid, 0, data);
    X509_add_ext(x, made, -1);
    X509_EXTENSION_free(made);
    ASN1_OCTET_STRING_free(data);
    ASN1_OBJECT_free(oid);
  }
  REQUIRE(X509_sign(x, key, EVP_sha256()) > 0);
  BIO* pem = BIO_new(BIO_s_mem());
  PEM_write_bio_X509(pem, x);
  X509_free(x);
  EVP_PKEY_free(key);
  Certificate read(PEM_read_bio_X509(pem, nullptr, nullptr, nullptr));
  BIO_free(pem);
  REQUIRE(read != nullptr);
  return read;
}

}  // namespace

TEST_CASE("client certificate: the role extension's UTF8String is the client's role") {
  const Certificate operator_certificate =
      make_certificate(der_string(V_ASN1_UTF8STRING, "operator"));
  const ClientCertificate read = read_client_certificate(*operator_certificate);
  CHECK(read.subject == "CN=plc-1,O=Plant");
  CHECK(read.role == std::optional<std::string>("operator"));
  CHECK(read.role_problem.empty());
  const Certificate german = make_certificate(der_string(V_ASN1_UTF8STRING, "Schichtführer"));
  CHECK(read_client_certificate(*german).role == std::optional<std::string>("Schichtführer"));
}

TEST_CASE("client certificate: without the role extension there is no role") {
  const ClientCertificate read = read_client_certificate(*make_certificate(std::nullopt));
  CHECK(read.subject == "CN=plc-1,O=Plant");
  CHECK_FALSE(read.role.has_value());
}

TEST_CASE("client certificate: a role extension without a UTF8String is an unknown role") {
  for (const std::string& extension :
       {der_string(V_ASN1_IA5STRING, "engineer"), std::string("\x0c\x08" "engin"),
        der_string(V_ASN1_UTF8STRING, "engineer") + "x"}) {
    const ClientCertificate read = read_client_certificate(*make_certificate(extension));
    CHECK(read.role == std::optional<std::string>(""));
    CHECK(read.role_problem == "its role extension holds no UTF8String");
  }
}
